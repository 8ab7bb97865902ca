// The pipelined training step against the serial one (docs/design.md §2): NR and ISNR trainers with the default
// settings on one scene, each in both schedules, take blocks of steps in turn (serial, pipelined, serial, ... in one
// process, so that load from other processes falls on both alike); each figure is the median over the rounds of a
// block's ms/step, the device's queue drained at the end of every block. The anchor is the serial schedule itself:
// the pipeline must not be slower on a CPU device, where host and device share the cores. Last, the host's incident
// loop alone in thread-µs a sample, beside the anchor issue 49 sets it.
// Usage: bench_pipeline [SCENE.xml] [rounds] [steps per block] (SCENE "" or none: the shared Cornell box, else the
// bundled one; 7 rounds of 10 steps).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/trainer.hpp"
#include "radiosity/training_lights.hpp"
#include "scene/scene.hpp"
#include "stage_report.hpp"

namespace {

using namespace clr;
namespace fs = std::filesystem;

// The anchor of the host's incident loop: thread-µs an incident sample on the H100 machine's host before next-event
// estimation (docs/nvidia.md), the bar with NEE included (issue 49) — on the H200's 16 cores the loop with NEE took
// 0.70, and its NR step became host-bound.
constexpr double kHostAnchorUs = 0.37;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The NR incident loop alone, with next-event estimation, on every host thread and with no device work in flight:
// thread-µs an incident sample, split by part. Samples are drawn for `rounds` batches of the trainer's size.
void print_host_incident_loop(const geometry::Geometry& geometry, const radiosity::TrainConfig& config, int rounds) {
  const geometry::SurfaceSampler sampler(geometry.scene());
  const geometry::LightSampler lights = radiosity::training_light_sampler(geometry.scene());
  radiosity::BatchSettings settings;
  settings.points = std::size_t(config.batch);
  settings.samples = std::size_t(config.samples);
  settings.next_event = true;
  radiosity::TrainingBatch batch;
  radiosity::HostStageTimes times;
  for (int round = -2; round < rounds; ++round) {  // two rounds to warm the allocations up, untimed
    batch.times = round < 0 ? nullptr : &times;
    radiosity::sample_training_points(sampler, geometry.scene(), settings, config.seed, std::uint64_t(round + 2),
                                      batch);
    radiosity::trace_incident(geometry, settings, config.seed, std::uint64_t(round + 2), {}, batch,
                              lights.empty() ? nullptr : &lights);
  }
  const double us = 1e6 / (double(rounds) * double(settings.points * settings.samples));
  const double loop = times.bsdf_cpu + times.tracing_cpu + times.next_event_cpu;
  std::printf(
      "host incident loop alone (NR, NEE on, %d batches): %.3f thread-µs a sample = BSDF %.3f + tracing %.3f + next "
      "events %.3f; anchor: at most %.2f (the H100 host's loop before NEE), %.2fx of it\n",
      rounds, loop * us, times.bsdf_cpu * us, times.tracing_cpu * us, times.next_event_cpu * us, kHostAnchorUs,
      loop * us / kHostAnchorUs);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path scene_path = fs::path(CLR_SHARED_SCENES) / "cornell-box" / "scene.xml";
  if (!fs::exists(scene_path)) scene_path = fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml";
  if (argc > 1 && *argv[1]) scene_path = argv[1];
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
  const int block = argc > 3 ? std::max(1, std::atoi(argv[3])) : 10;
  const auto scene = scene::load_scene(scene_path);
  const geometry::Geometry geometry(scene);
  cl::Context ctx(cl::select_device(""));
  const fs::path tmp = fs::temp_directory_path() / ("clr_bench_pipeline_" + std::to_string(::getpid()));
  fs::remove_all(tmp);

  struct Row {
    const char* method;
    radiosity::StepSchedule schedule;
    std::unique_ptr<radiosity::Trainer> trainer;
    std::vector<double> ms;
    radiosity::HostStageTimes host;
    double device_s = 0, wall_s = 0;
  };
  std::vector<Row> rows;
  radiosity::TrainConfig config;
  config.steps = 1000000;
  config.log_every = 1000000;
  config.checkpoint_every = 1000000;
  config.guide_warmup = 0.0;  // ISNR at the guided share the run settles at
  for (const auto method : {radiosity::Method::Nr, radiosity::Method::Isnr})
    for (const auto schedule : {radiosity::StepSchedule::Serial, radiosity::StepSchedule::Pipelined}) {
      config.method = method;
      const char* name = method == radiosity::Method::Nr ? "NR" : "ISNR";
      auto t = std::make_unique<radiosity::Trainer>(ctx, geometry, config,
                                                    tmp / (std::string(name) + std::to_string(int(schedule))), false);
      t->set_schedule(schedule);
      rows.push_back({name, schedule, std::move(t), {}, {}, 0, 0});
    }
  for (auto& r : rows)  // warm-up: program builds, buffer growth, the GEMM probe
    for (int i = 0; i < 3; ++i) r.trainer->step();
  ctx.finish();
  for (auto& r : rows) r.trainer->time_host_stages(&r.host);
  for (int round = 0; round < rounds; ++round)
    for (auto& r : rows) {
      const bench::BlockTime t = bench::time_block(ctx, *r.trainer, block);
      r.ms.push_back(1e3 * t.wall_s / block);
      r.wall_s += t.wall_s;
      r.device_s += t.device_s;
    }
  fs::remove_all(tmp);

  std::printf("%s on %s, batch %d x %d, %d rounds of %d steps, schedules alternating in one process\n",
              scene_path.c_str(), ctx.device().describe().c_str(), rows[0].trainer->config().batch,
              rows[0].trainer->config().samples, rounds, block);
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const double serial = median(rows[i].ms), piped = median(rows[i + 1].ms);
    // Adjacent blocks see about the same load from other processes: their ratio, round by round, is the fairer one.
    std::vector<double> ratios;
    for (int round = 0; round < rounds; ++round) ratios.push_back(rows[i + 1].ms[round] / rows[i].ms[round]);
    std::printf(
        "%-4s  serial %7.1f ms/step  pipelined %7.1f ms/step  (medians; pipelined/serial %.3f, median of the rounds' "
        "ratios %.3f)\n",
        rows[i].method, serial, piped, piped / serial, median(ratios));
    for (std::size_t j = i; j < i + 2; ++j) {
      std::printf("      %-9s blocks:", j == i ? "serial" : "pipelined");
      for (const double ms : rows[j].ms) std::printf(" %.1f", ms);
      std::printf("\n");
    }
    for (std::size_t j = i; j < i + 2; ++j)
      bench::print_stages((std::string(rows[j].method) + (j == i ? " serial" : " pipelined")).c_str(), rows[j].host,
                          rows[j].device_s, rows[j].wall_s);
  }
  print_host_incident_loop(geometry, rows[0].trainer->config(), 4 * rounds);
  return 0;
}
