#include "cl/context.hpp"

#include <algorithm>
#include <stdexcept>

#include "cl/error.hpp"
#include "cl/no_platform.hpp"

namespace clr::cl {

Context::Context(DeviceInfo device) : device_(std::move(device)) {
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
}

void Context::finish() const { CLR_CL_CHECK(clFinish(queue_.get())); }

const Program& Context::program(const std::vector<std::string>& files, const std::string& options) {
  std::string key = options + "|";
  for (const auto& f : files) key += f + ";";
  auto& slot = programs_[key];
  if (!slot) {
    try {
      slot = std::make_unique<Program>(*this, files, options);
    } catch (...) {
      programs_.erase(key);
      throw;
    }
    ++programs_built_;
  }
  return *slot;
}

void Context::on_alloc(std::uint64_t bytes) {
  bytes_in_use_ += bytes;
  peak_bytes_ = std::max(peak_bytes_, bytes_in_use_);
}

}  // namespace clr::cl
