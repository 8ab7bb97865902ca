#pragma once
// Timed probes that pick an implementation per device (the GEMM backend and tile, the small-MLP path) and their
// cache on disk ($XDG_CACHE_HOME/clradiosity/gemm_probe.json, else ~/.cache/...), keyed by device name, driver
// version, the type the device reports and any emulated limits: {device key: {candidate: seconds}}. A damaged or
// unwritable cache costs a re-probe, never a failure.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "cl/context.hpp"

namespace clr::nn {

class ProbeCache {
 public:
  explicit ProbeCache(const cl::Context& ctx);
  // The cached seconds of `candidate`, or `measure()`'s (then cached).
  double seconds(const std::string& candidate, const std::function<double()>& measure);
  // Writes the cache back if anything was measured.
  ~ProbeCache();

  // The best of three timed runs of `run` (after one warm-up run) on the context's queue.
  static double time_best_of_three(const cl::Context& ctx, const std::function<void()>& run);

 private:
  std::string file_, key_;
  nlohmann::json cache_ = nlohmann::json::object();
  bool measured_ = false;
};

}  // namespace clr::nn
