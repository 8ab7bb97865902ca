#pragma once
// A typed device buffer. Allocation checks the device's max single allocation (1 GiB on PoCL) and names the
// buffer's size when it is exceeded, so callers chunk their passes instead of meeting CL_INVALID_BUFFER_SIZE.
#include <CL/cl.h>

#include <algorithm>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "cl/error.hpp"
#include "cl/handle.hpp"
#include "common/address_space.hpp"

namespace clr::cl {

template <typename T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& ctx, std::size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE) : ctx_(&ctx), count_(count) {
    const std::uint64_t bytes = this->bytes();
    if (bytes > ctx.device().max_alloc_bytes)
      throw std::runtime_error("buffer of " + std::to_string(bytes) + " bytes exceeds the device's max allocation of " +
                               std::to_string(ctx.device().max_alloc_bytes) + " bytes on " + ctx.device().name);
    // A CPU device's buffers are this process's memory, backed at first use, where PoCL asserts when it cannot:
    // weighed first against the address-space limit, with every live buffer counted as not yet backed.
    if (ctx.device().type == DeviceType::Cpu) require_address_space(bytes, ctx.bytes_in_use(), "an OpenCL buffer");
    cl_int status = CL_SUCCESS;
    // A zero-sized cl_mem is invalid; empty buffers hold one element so kernels can still take them as arguments.
    mem_ = MemHandle(clCreateBuffer(ctx.get(), flags, std::max<std::size_t>(bytes, sizeof(T)), nullptr, &status));
    CLR_CL_CHECK(status);
    ctx.on_alloc(bytes);
  }
  Buffer(Context& ctx, std::span<const T> data) : Buffer(ctx, data.size()) { write(data); }
  Buffer(Buffer&& o) noexcept { swap(o); }
  Buffer& operator=(Buffer&& o) noexcept {
    Buffer tmp(std::move(o));
    swap(tmp);
    return *this;
  }
  ~Buffer() {
    if (ctx_ && mem_) ctx_->on_free(bytes());
  }

  std::size_t size() const { return count_; }
  std::uint64_t bytes() const { return std::uint64_t(count_) * sizeof(T); }
  cl_mem get() const { return mem_.get(); }

  void write(std::span<const T> data, std::size_t offset = 0) {
    check_range(offset, data.size());
    if (data.empty()) return;
    CLR_CL_CHECK(clEnqueueWriteBuffer(ctx_->queue(), mem_.get(), CL_TRUE, offset * sizeof(T), data.size_bytes(),
                                      data.data(), 0, nullptr, ctx_->event_slot()));
  }
  void read(std::span<T> out, std::size_t offset = 0) const {
    check_range(offset, out.size());
    if (out.empty()) return;
    CLR_CL_CHECK(clEnqueueReadBuffer(ctx_->queue(), mem_.get(), CL_TRUE, offset * sizeof(T), out.size_bytes(),
                                     out.data(), 0, nullptr, ctx_->event_slot()));
  }
  std::vector<T> read() const {
    std::vector<T> out(count_);
    read(out);
    return out;
  }
  // The first src.size() values become src's, on the device (after everything enqueued before).
  void copy_from(const Buffer& src) {
    check_range(0, src.size());
    if (src.count_ == 0) return;
    CLR_CL_CHECK(
        clEnqueueCopyBuffer(ctx_->queue(), src.get(), mem_.get(), 0, 0, src.bytes(), 0, nullptr, ctx_->event_slot()));
  }
  void fill(const T& value) {
    if (count_ == 0) return;
    // Oclgrind's uninitialised-value check does not count clEnqueueFillBuffer as a write (21.10: a kernel reading a
    // filled buffer is reported; the same data written is not), so on the simulator a fill is a host write and the
    // check stays on for everything else. Real devices keep the cheap device-side fill.
    if (ctx_->device().simulator) {
      write(std::vector<T>(count_, value));
      return;
    }
    CLR_CL_CHECK(
        clEnqueueFillBuffer(ctx_->queue(), mem_.get(), &value, sizeof(T), 0, bytes(), 0, nullptr, ctx_->event_slot()));
  }

 private:
  void swap(Buffer& o) noexcept {
    std::swap(ctx_, o.ctx_);
    std::swap(count_, o.count_);
    std::swap(mem_, o.mem_);
  }
  void check_range(std::size_t offset, std::size_t n) const {
    if (offset + n > count_)
      throw std::out_of_range("buffer access [" + std::to_string(offset) + ", " + std::to_string(offset + n) +
                              ") outside a buffer of " + std::to_string(count_) + " elements");
  }

  Context* ctx_ = nullptr;
  std::size_t count_ = 0;
  MemHandle mem_;
};

// Grow-only buffers reused across steps: re-created only when `count` (at least one) elements no longer fit.
template <typename T>
void reserve(Context& ctx, Buffer<T>& buf, std::size_t count) {
  if (buf.size() < std::max<std::size_t>(1, count)) buf = Buffer<T>(ctx, std::max<std::size_t>(1, count));
}
template <typename T>
void upload(Context& ctx, Buffer<T>& buf, const std::vector<T>& host) {
  reserve(ctx, buf, host.size());
  if (!host.empty()) buf.write(host);
}

}  // namespace clr::cl
