#pragma once
// A training step's host stages beside the device's busy time (issue: the host must keep up with a GPU), printed
// by bench_guide and bench_pipeline. The host's stages come from Trainer::time_host_stages, the device's time from
// its profiled commands (cl::Context::record_device_time): a step whose host work exceeds its device time is
// host-bound on that machine, whatever the device.
#include <chrono>
#include <cstdio>

#include "cl/context.hpp"
#include "radiosity/trainer.hpp"

namespace clr::bench {

struct BlockTime {
  double wall_s = 0, device_s = 0;
};

// `steps` steps of `trainer`, the queue drained at the end: their wall time and the device's busy time in them.
inline BlockTime time_block(cl::Context& ctx, radiosity::Trainer& trainer, int steps) {
  ctx.record_device_time(true);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) trainer.step();
  ctx.finish();
  BlockTime t;
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  t.device_s = ctx.take_device_seconds();
  ctx.record_device_time(false);
  return t;
}

inline void print_stages(const char* label, const radiosity::HostStageTimes& t, double device_s, double wall_s) {
  const double n = double(t.steps ? t.steps : 1), ms = 1e3 / n;
  std::printf(
      "  %-16s per step: wall %.2f ms | device busy %.2f ms | host work %.2f ms = points %.2f + incident loop %.2f "
      "(thread-ms: BSDF %.2f, tracing %.2f, next events %.2f) + packing %.2f + uploads %.2f | waiting for the "
      "device: guided directions %.2f, pinned memory %.2f ms | %s\n",
      label, wall_s * ms, device_s * ms, t.host_work() * ms, t.points * ms, t.incident * ms, t.bsdf_cpu * ms,
      t.tracing_cpu * ms, t.next_event_cpu * ms, t.packing * ms, t.uploads * ms, t.guide_read * ms, t.device_wait * ms,
      t.host_work() > device_s ? "host-bound (host work > device busy)" : "device-bound (device busy >= host work)");
}

}  // namespace clr::bench
