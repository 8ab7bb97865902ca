#include "cl/kernel.hpp"

#include <algorithm>

#include "cl/context.hpp"

namespace clr::cl {
namespace {
std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }
}  // namespace

Kernel::Kernel(const Context& ctx, KernelHandle kernel, std::string name)
    : ctx_(&ctx), kernel_(std::move(kernel)), name_(std::move(name)) {
  CLR_CL_CHECK(clGetKernelWorkGroupInfo(kernel_.get(), ctx.device().device, CL_KERNEL_WORK_GROUP_SIZE,
                                        sizeof(work_group_size_), &work_group_size_, nullptr));
  work_group_size_ = std::min(work_group_size_, ctx.device().max_work_group_size);
  // Queried before any argument is set, so this is the kernel's own __local variables only.
  cl_ulong local = 0;
  CLR_CL_CHECK(clGetKernelWorkGroupInfo(kernel_.get(), ctx.device().device, CL_KERNEL_LOCAL_MEM_SIZE, sizeof(local),
                                        &local, nullptr));
  static_local_bytes_ = local;
}

void Kernel::set_arg(cl_uint i, const LocalMemory& l) {
  if (local_arg_bytes_.size() <= i) local_arg_bytes_.resize(i + 1, 0);
  const std::uint64_t before = local_arg_bytes_[i];
  local_arg_bytes_[i] = l.bytes;
  try {
    check_local_memory();
  } catch (...) {
    local_arg_bytes_[i] = before;  // the argument was not set
    throw;
  }
  set_raw(i, l.bytes, nullptr);
}

void Kernel::check_local_memory() const {
  const std::uint64_t bytes = local_mem_bytes();
  if (bytes > ctx_->device().local_mem_bytes)
    throw Error(CL_OUT_OF_RESOURCES, "kernel " + name_ + ": " + std::to_string(bytes) +
                                         " bytes of __local memory a work-group exceed the device's " +
                                         std::to_string(ctx_->device().local_mem_bytes) + " on " + ctx_->device().name);
}

std::uint64_t Kernel::local_mem_bytes() const {
  std::uint64_t total = static_local_bytes_;
  for (const auto b : local_arg_bytes_) total += b;
  return total;
}

void Kernel::set_raw(cl_uint i, std::size_t size, const void* value) {
  const cl_int status = clSetKernelArg(kernel_.get(), i, size, value);
  // An argument set by value or as a buffer after being __local no longer takes local memory.
  if (value && i < local_arg_bytes_.size()) local_arg_bytes_[i] = 0;
  if (status != CL_SUCCESS)
    throw Error(status, "clSetKernelArg(" + name_ + ", arg " + std::to_string(i) + ", " + std::to_string(size) +
                            " bytes) failed with " + status_name(status));
}

void Kernel::launch(std::size_t global, std::size_t local) const {
  if (global == 0) return;
  if (local == 0) local = std::min<std::size_t>(64, work_group_size_);
  const std::size_t padded = round_up(global, local);
  enqueue(1, &padded, &local);
}

void Kernel::launch(std::array<std::size_t, 2> global, std::array<std::size_t, 2> local) const {
  if (global[0] == 0 || global[1] == 0) return;
  const std::array<std::size_t, 2> padded{round_up(global[0], local[0]), round_up(global[1], local[1])};
  enqueue(2, padded.data(), local.data());
}

void Kernel::enqueue(cl_uint dims, const std::size_t* global, const std::size_t* local) const {
  std::size_t group = 1;
  for (cl_uint d = 0; d < dims; ++d) group *= local[d];
  if (group > work_group_size_)
    throw Error(CL_INVALID_WORK_GROUP_SIZE, "kernel " + name_ + ": work-group of " + std::to_string(group) +
                                                " exceeds its limit of " + std::to_string(work_group_size_) + " on " +
                                                ctx_->device().name);
  check_local_memory();
  const cl_int status = clEnqueueNDRangeKernel(ctx_->queue(), kernel_.get(), dims, nullptr, global, local, 0, nullptr,
                                               ctx_->event_slot());
  if (status != CL_SUCCESS)
    throw Error(status, "clEnqueueNDRangeKernel(" + name_ + ") failed with " + status_name(status));
}

}  // namespace clr::cl
