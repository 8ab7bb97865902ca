#pragma once
// Work on the context's in-order queue that the host does not wait for (docs/design.md §2, the pipelined step).
//
// flush: submits what is enqueued so far. Some drivers (NVIDIA's) hold enqueued commands until a flush or a
// blocking call, so without it the device would sit idle while the host prepares the next step.
//
// PinnedUpload: one host-to-device stream that is sent again every step (a training batch's per-point and per-sample
// arrays): the data is copied into pinned host memory (CL_MEM_ALLOC_HOST_PTR, mapped once for the life of the stream)
// and written to the device buffer without blocking. A GPU DMAs from pinned memory directly (from pageable memory the
// driver stages through its own pinned buffer and the write blocks the host), and the host returns at once, so it
// can prepare the next step while the transfer and the kernels after it run (docs/design.md §2, the pipeline).
// The event of the last write guards the pinned memory: the next send waits for it before overwriting, so the
// caller's vector may change as soon as send returns. Pinned memory is host memory: it is not counted as device
// memory (Context's accounting).
#include <CL/cl.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <span>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/error.hpp"
#include "cl/handle.hpp"
#include "common/address_space.hpp"

namespace clr::cl {

inline void flush(const Context& ctx) { CLR_CL_CHECK(clFlush(ctx.queue())); }

// Pinned host memory (CL_MEM_ALLOC_HOST_PTR, mapped once for its life) that one stream of transfers goes through;
// the event of the last transfer guards it.
template <typename T>
class PinnedMemory {
 public:
  PinnedMemory() = default;
  PinnedMemory(const PinnedMemory&) = delete;
  PinnedMemory& operator=(const PinnedMemory&) = delete;
  ~PinnedMemory() { release(); }

 protected:
  void wait() {
    if (last_) {
      const cl_event e = last_.get();
      const auto start = std::chrono::steady_clock::now();
      CLR_CL_CHECK(clWaitForEvents(1, &e));
      ctx_->add_wait(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      last_ = EventHandle();
    }
  }
  // Capacity grows by half again over the request, so a batch whose size varies a little (the compacted lookup
  // rows) does not re-pin every step.
  void reserve_host(Context& ctx, std::size_t count, cl_mem_flags access, cl_map_flags map) {
    if (count <= capacity_) return;
    release();
    capacity_ = count + count / 2;
    if (ctx.device().type == DeviceType::Cpu)  // as cl::Buffer: host memory, weighed before PoCL maps it
      require_address_space(capacity_ * sizeof(T), ctx.bytes_in_use(), "a pinned OpenCL buffer");
    cl_int status = CL_SUCCESS;
    pinned_ =
        MemHandle(clCreateBuffer(ctx.get(), access | CL_MEM_ALLOC_HOST_PTR, capacity_ * sizeof(T), nullptr, &status));
    CLR_CL_CHECK(status);
    ctx_ = &ctx;
    void* p = clEnqueueMapBuffer(ctx.queue(), pinned_.get(), CL_TRUE, map, 0, capacity_ * sizeof(T), 0, nullptr,
                                 nullptr, &status);
    CLR_CL_CHECK(status);
    mapped_ = static_cast<T*>(p);
  }
  // Unmapping is enqueued behind the last transfer through the mapping (its event: a download runs on the transfer
  // queue), and the runtime keeps the buffer until the commands using it are done, so nothing waits here. A
  // destructor does not throw: a failure (only at teardown of a broken context) is ignored.
  void release() noexcept {
    if (!pinned_) return;
    const cl_event last = last_.get();
    if (mapped_)
      clEnqueueUnmapMemObject(ctx_->queue(), pinned_.get(), mapped_, last ? 1 : 0, last ? &last : nullptr, nullptr);
    mapped_ = nullptr;
    last_ = EventHandle();
    pinned_ = MemHandle();
    capacity_ = 0;
  }

  MemHandle pinned_;
  const Context* ctx_ = nullptr;  // the queue of the mapping, and where the time blocked in wait() is counted
  T* mapped_ = nullptr;
  std::size_t capacity_ = 0;
  EventHandle last_;
};

template <typename T>
class PinnedUpload : public PinnedMemory<T> {
 public:
  // dst (grown to fit, at least one element) receives `host`; returns before the transfer ends.
  void send(Context& ctx, Buffer<T>& dst, const std::vector<T>& host) {
    reserve(ctx, dst, host.size());
    if (host.empty()) return;
    this->wait();
    this->reserve_host(ctx, host.size(), CL_MEM_READ_ONLY, CL_MAP_WRITE);
    std::memcpy(this->mapped_, host.data(), host.size() * sizeof(T));
    cl_event done = nullptr;
    CLR_CL_CHECK(clEnqueueWriteBuffer(ctx.queue(), dst.get(), CL_FALSE, 0, host.size() * sizeof(T), this->mapped_, 0,
                                      nullptr, &done));
    this->last_ = EventHandle(done);
    ctx.record(done);
  }
};

// The reverse stream: a read the host starts, does other work, and collects later (the pipelined step's guided
// directions, drawn on the device ahead of the step that traces them). The read runs on the context's transfer
// queue behind a marker of the main queue, so the kernels enqueued after it do not wait for it (on a GPU the copy
// engine overlaps them). The other side of that: a later command that overwrites `src` must come after wait().
template <typename T>
class PinnedDownload : public PinnedMemory<T> {
 public:
  // Starts reading the first `count` values of `src` (after everything enqueued before); returns at once.
  void start(Context& ctx, const Buffer<T>& src, std::size_t count) {
    this->wait();
    this->reserve_host(ctx, std::max<std::size_t>(count, 1), CL_MEM_WRITE_ONLY, CL_MAP_READ);
    count_ = count;
    if (count == 0) return;
    cl_event marker = nullptr, done = nullptr;
    CLR_CL_CHECK(clEnqueueMarkerWithWaitList(ctx.queue(), 0, nullptr, &marker));
    const EventHandle after(marker);
    // Another queue may wait only on events of a flushed one.
    CLR_CL_CHECK(clFlush(ctx.queue()));
    CLR_CL_CHECK(clEnqueueReadBuffer(ctx.transfer_queue(), src.get(), CL_FALSE, 0, count * sizeof(T), this->mapped_, 1,
                                     &marker, &done));
    CLR_CL_CHECK(clFlush(ctx.transfer_queue()));
    this->last_ = EventHandle(done);
  }
  // Waits for the read started last; its values stay valid until the next start.
  std::span<const T> result() {
    this->wait();
    return {this->mapped_, count_};
  }
  // Waits for the read started last, before a command that overwrites its source.
  void wait() { PinnedMemory<T>::wait(); }

 private:
  std::size_t count_ = 0;
};

}  // namespace clr::cl
