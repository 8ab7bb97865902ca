#pragma once
// A kernel with typed argument setting and a launch that pads the global size to a multiple of the
// work-group size (kernels bounds-check against a count argument) and, before enqueueing, refuses a work-group the
// kernel cannot run (CL_KERNEL_WORK_GROUP_SIZE, capped by the device's limit as DeviceInfo reports it, so
// CLRADIOSITY_EMULATE_LIMITS applies) or whose __local memory (the kernel's own plus LocalMemory arguments)
// exceeds the device's: a clear error naming the kernel instead of CL_INVALID_WORK_GROUP_SIZE or
// CL_OUT_OF_RESOURCES from the driver.
#include <CL/cl.h>

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "cl/error.hpp"
#include "cl/handle.hpp"

namespace clr::cl {

class Context;
template <typename T>
class Buffer;

// __local memory of a given size in bytes, passed as a kernel argument.
struct LocalMemory {
  std::size_t bytes;
};

class Kernel {
 public:
  Kernel(const Context& ctx, KernelHandle kernel, std::string name);

  // Sets every argument in order: Buffer<T> as its cl_mem, LocalMemory as __local space, anything else by value.
  template <typename... Args>
  Kernel& args(const Args&... a) {
    cl_uint i = 0;
    (set_arg(i++, a), ...);
    return *this;
  }

  // 1-D and 2-D launches. local == 0 picks the preferred size (at most 64, the kernel's own limit respected).
  void launch(std::size_t global, std::size_t local = 0) const;
  void launch(std::array<std::size_t, 2> global, std::array<std::size_t, 2> local) const;

  std::size_t work_group_size() const { return work_group_size_; }
  // __local bytes one work-group of the next launch uses: the kernel's own __local variables and the LocalMemory
  // arguments set.
  std::uint64_t local_mem_bytes() const;
  const std::string& name() const { return name_; }
  cl_kernel get() const { return kernel_.get(); }

 private:
  template <typename T>
  void set_arg(cl_uint i, const Buffer<T>& b) {
    const cl_mem m = b.get();
    set_raw(i, sizeof(cl_mem), &m);
  }
  void set_arg(cl_uint i, const LocalMemory& l);
  template <typename T>
  void set_arg(cl_uint i, const T& v) {
    static_assert(std::is_trivially_copyable_v<T>, "kernel arguments by value must be trivially copyable");
    set_raw(i, sizeof(T), &v);
  }
  void set_raw(cl_uint i, std::size_t size, const void* value);
  void check_local_memory() const;
  void enqueue(cl_uint dims, const std::size_t* global, const std::size_t* local) const;

  const Context* ctx_;
  KernelHandle kernel_;
  std::string name_;
  std::size_t work_group_size_ = 0;
  std::uint64_t static_local_bytes_ = 0;
  std::vector<std::uint64_t> local_arg_bytes_;  // by argument index; 0 for arguments that are not __local
};

}  // namespace clr::cl
