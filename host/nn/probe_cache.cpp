#include "nn/probe_cache.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cl/error.hpp"
#include "common/atomic_file.hpp"
#include "common/input_file.hpp"

namespace clr::nn {
namespace {

std::string cache_file() {
  std::filesystem::path dir;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    dir = x;
  else if (const char* h = std::getenv("HOME"); h && *h)
    dir = std::filesystem::path(h) / ".cache";
  else
    return {};
  return (dir / "clradiosity" / "gemm_probe.json").string();
}

}  // namespace

ProbeCache::ProbeCache(const cl::Context& ctx)
    // The type and the emulated limits are part of the key: they change the candidates' launch shapes, so a context
    // that reports itself as a GPU (the tests' GPU-shaped PoCL) must not read a CPU's times of the same device.
    : file_(cache_file()),
      key_(ctx.device().platform_name + " | " + ctx.device().name + " | " + ctx.device().driver_version + " | " +
           cl::type_name(ctx.device().type) + (ctx.device().emulated.empty() ? "" : " | " + ctx.device().emulated)) {
  if (file_.empty()) return;
  // The cache is ours, not the user's: one that cannot be read (a damaged file, a FIFO in its place) is probed anew.
  try {
    if (std::filesystem::exists(file_)) cache_ = read_json_file(file_, "GEMM probe cache");
    if (!cache_.is_object() || (cache_.contains(key_) && !cache_[key_].is_object())) cache_ = nlohmann::json::object();
  } catch (const std::exception&) {
    cache_ = nlohmann::json::object();
  }
}

double ProbeCache::seconds(const std::string& candidate, const std::function<double()>& measure) {
  nlohmann::json& times = cache_[key_];
  if (times.is_null()) times = nlohmann::json::object();
  if (!times.contains(candidate) || !times[candidate].is_number()) {
    times[candidate] = measure();
    measured_ = true;
  }
  return times[candidate].get<double>();
}

ProbeCache::~ProbeCache() {
  if (!measured_ || file_.empty()) return;
  try {
    write_record_atomically(file_, cache_.dump(2) + "\n", "GEMM probe cache");
  } catch (const std::exception&) {
    // best effort: an unwritable cache only costs a re-probe next time
  }
}

double ProbeCache::time_best_of_three(const cl::Context& ctx, const std::function<void()>& run) {
  run();  // warm-up: builds kernels, grows buffers
  ctx.finish();
  double best = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    ctx.finish();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace clr::nn
