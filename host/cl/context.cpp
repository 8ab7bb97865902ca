#include "cl/context.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "cl/error.hpp"
#include "cl/no_platform.hpp"
#include "common/stop_signal.hpp"

namespace clr::cl {

Context::Context(DeviceInfo device) : device_(std::move(device)) {
  const std::lock_guard<std::recursive_mutex> lock(opencl_startup_mutex());
  // Found before any work: each kernel build would otherwise fail with an empty build log.
  if (const std::string cause = pocl_cache_cause(device_.platform_name); !cause.empty())
    throw std::runtime_error(cause);
  cl_int status = CL_SUCCESS;
  const cl_context_properties props[] = {CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(device_.platform),
                                         0};
  context_ = ContextHandle(clCreateContext(props, 1, &device_.device, nullptr, nullptr, &status));
  CLR_CL_CHECK(status);
  // Profiling is always on: benchmarks read kernel times from events, and its cost is negligible.
  queue_ = QueueHandle(clCreateCommandQueue(context_.get(), device_.device, CL_QUEUE_PROFILING_ENABLE, &status));
  CLR_CL_CHECK(status);
  reclaim_signals();
}

Context::~Context() {
  for (const Timed& t : timed_) t.release();
}

cl_command_queue Context::transfer_queue() const {
  if (!transfer_) {
    cl_int status = CL_SUCCESS;
    transfer_ = QueueHandle(clCreateCommandQueue(context_.get(), device_.device, 0, &status));
    CLR_CL_CHECK(status);
  }
  return transfer_.get();
}

void Context::finish() const {
  CLR_CL_CHECK(clFinish(queue_.get()));
  if (transfer_) CLR_CL_CHECK(clFinish(transfer_.get()));
}

const Program& Context::program(const std::vector<std::string>& files, const std::string& options) {
  std::string key = options + "|";
  for (const auto& f : files) key += f + ";";
  auto& slot = programs_[key];
  if (!slot) {
    try {
      slot = std::make_unique<Program>(*this, files, options);
    } catch (...) {
      programs_.erase(key);
      reclaim_signals();
      throw;
    }
    reclaim_signals();  // the compiler may have installed its handlers
    ++programs_built_;
    // A test lane's check that every kernel builds clean: its warnings fail the build there (and stay out of the
    // user's terminal everywhere else, in the program's build log).
    if (const char* strict = std::getenv("CLRADIOSITY_KERNEL_WARNINGS");
        strict && std::string(strict) == "error" && has_warning(slot->build_log())) {
      const std::string log = slot->build_log(), names = slot->names();
      programs_.erase(key);
      throw Error(CL_BUILD_PROGRAM_FAILURE, "OpenCL program [" + names + "] with options '" + options +
                                                "' built with warnings (CLRADIOSITY_KERNEL_WARNINGS=error):\n" + log);
    }
  }
  return *slot;
}

cl_event* Context::event_slot() const {
  if (!recording_) return nullptr;
  return &timed_.emplace_back().command;
}

cl_event* Context::span_slot() const {
  if (!recording_) return nullptr;
  Timed& t = timed_.emplace_back();
  CLR_CL_CHECK(clEnqueueMarkerWithWaitList(queue_.get(), 0, nullptr, &t.opened));
  return &t.command;
}

void Context::record(cl_event event) const {
  if (!recording_ || !event) return;
  CLR_CL_CHECK(clRetainEvent(event));
  timed_.emplace_back().command = event;
}

double Context::take_device_seconds() {
  finish();
  const auto at = [](cl_event e, cl_profiling_info what) {
    cl_ulong ns = 0;
    CLR_CL_CHECK(clGetEventProfilingInfo(e, what, sizeof ns, &ns, nullptr));
    return ns;
  };
  cl_ulong busy_ns = 0;
  std::deque<Timed> timed;
  timed.swap(timed_);
  try {
    for (const Timed& t : timed) {
      if (!t.command) continue;  // an enqueue that failed
      const cl_ulong start =
          t.opened ? at(t.opened, CL_PROFILING_COMMAND_END) : at(t.command, CL_PROFILING_COMMAND_START);
      const cl_ulong end = at(t.command, CL_PROFILING_COMMAND_END);
      busy_ns += end > start ? end - start : 0;
    }
  } catch (...) {
    timed.swap(timed_);  // the destructor releases them
    throw;
  }
  for (const Timed& t : timed) t.release();
  return 1e-9 * double(busy_ns);
}

void Context::on_alloc(std::uint64_t bytes) {
  bytes_in_use_ += bytes;
  peak_bytes_ = std::max(peak_bytes_, bytes_in_use_);
}

}  // namespace clr::cl
