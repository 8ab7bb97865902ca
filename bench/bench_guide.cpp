// The I-Module's share of an ISNR training step (the target: ≤ 10 %, the paper's overhead ≈ 10 %): NR and
// ISNR trainers with the default settings on one scene take interleaved blocks of steps; the share is
// (t_ISNR − t_NR) / t_ISNR, printed beside the anchor (the paper's ≈ 10 %, and +18 % to +38 % implied by its
// Table 1), then the I-Module's stages one by one. Usage: bench_guide [SCENE.xml] [rounds] (default: the shared
// Cornell box, 5 rounds of 20 steps).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>

#include "cl/context.hpp"
#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "nn/probe_cache.hpp"
#include "radiosity/guide/vmf_mixture.hpp"
#include "radiosity/trainer.hpp"
#include "scene/scene.hpp"
#include "stage_report.hpp"

namespace {

using namespace clr;
namespace fs = std::filesystem;

// The I-Module's stages on a training batch's shape (M points, N samples, random rows and targets), each timed to
// completion: where its share of a step goes.
void print_stages(cl::Context& ctx, const nn::NetworkConfig& guide_config, std::size_t M, std::size_t N) {
  nn::Network guide(ctx, guide_config);
  radiosity::VmfMixture vmf(ctx);
  Pcg32 rng(0, 3);
  const auto uniform = [&](std::size_t n, float lo, float hi) {
    std::vector<float> v(n);
    for (auto& x : v) x = lo + (hi - lo) * rng.next_float();
    return v;
  };
  cl::Buffer<float> rows(ctx, std::span<const float>(uniform(M * nn::kRawInputs, 0.0f, 1.0f))),
      u(ctx, std::span<const float>(uniform(M * N * 3, 0.0f, 1.0f))), dirs(ctx, M * N * 3),
      bsdf_pdf(ctx, std::span<const float>(uniform(M * N, 0.05f, 1.0f))), pdf(ctx, M * N), q(ctx, M * N),
      weight(ctx, std::span<const float>(uniform(M * N * 3, 0.0f, 1.0f))),
      emitted(ctx, std::span<const float>(uniform(M * N * 3, 0.0f, 0.1f))),
      radiance(ctx, std::span<const float>(uniform(M * N * 3, 0.0f, 1.0f))), d_raw(ctx, M * radiosity::kVmfRaw),
      scattered(ctx, std::span<const float>(uniform(M * 3, 0.1f, 1.0f)));
  std::vector<float> up(M * 3, 0.0f);
  for (std::size_t m = 0; m < M; ++m) up[3 * m + 2] = 1.0f;
  cl::Buffer<float> normals(ctx, std::span<const float>(up));
  std::vector<int> lookup_host(M * N);
  for (std::size_t s = 0; s < M * N; ++s) lookup_host[s] = int(s);
  cl::Buffer<int> lookup(ctx, std::span<const int>(lookup_host));
  nn::NetworkContext fwd;
  const std::pair<const char*, std::function<void()>> stages[] = {
      {"forward (activations kept)", [&] { guide.forward_train(rows, M, fwd); }},
      {"decode lobes", [&] { vmf.decode(fwd.output(), normals, M); }},
      {"sample directions", [&] { vmf.sample(u, N, dirs); }},
      {"read directions back", [&] { (void)dirs.read(); }},
      {"mixture pdf", [&] { vmf.mixture_pdf(dirs, bsdf_pdf, N, 0.5f, pdf, q); }},
      {"KL/IKL gradient",
       [&] {
         vmf.loss({dirs, bsdf_pdf, pdf, weight, emitted, lookup, radiance, scattered}, N, true, d_raw);
       }},
      {"backward", [&] { guide.backward(fwd, d_raw); }},
      {"  of which MLP (no dX)", [&] { guide.mlp().backward(fwd.mlp, d_raw, nullptr, 0); }},
      {"Adam", [&] { guide.adam_step(); }},
  };
  double total = 0;
  std::printf("I-Module stages at M = %zu, N = %zu:\n", M, N);
  for (const auto& [name, run] : stages) {
    // Its warm-up run also leaves the state the next stage reads.
    const double best = nn::ProbeCache::time_best_of_three(ctx, run);
    total += best;
    std::printf("  %-28s %6.2f ms\n", name, 1e3 * best);
  }
  std::printf("  %-28s %6.2f ms (the host's BSDF evaluations at guided directions come on top)\n", "total",
              1e3 * total);
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path scene_path = argc > 1 ? fs::path(argv[1]) : fs::path(CLR_SHARED_SCENES) / "cornell-box" / "scene.xml";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 5;
  constexpr int kBlock = 20;
  const auto scene = scene::load_scene(scene_path);
  const geometry::Geometry geometry(scene);
  cl::Context ctx(cl::select_device(""));
  const fs::path tmp = fs::temp_directory_path() / ("clr_bench_guide_" + std::to_string(::getpid()));
  fs::remove_all(tmp);

  radiosity::TrainConfig config;
  config.steps = 1000000;
  config.log_every = 1000000;
  config.checkpoint_every = 1000000;
  config.guide_warmup = 0.0;  // ISNR at the guided share the run settles at
  // NR, ISNR (its default, the lagged guide: guided directions traced while the device runs the step before), and
  // ISNR with the unlagged guide (the host traces them only after the step before has finished).
  struct Row {
    const char* name;
    std::unique_ptr<radiosity::Trainer> trainer;
    radiosity::HostStageTimes host;
    double step_s = 0, device_s = 0;
  };
  Row rows[3] = {{"NR", nullptr, {}, 0, 0}, {"ISNR", nullptr, {}, 0, 0}, {"ISNR lag 0", nullptr, {}, 0, 0}};
  for (int i = 0; i < 3; ++i) {
    config.method = i == 0 ? radiosity::Method::Nr : radiosity::Method::Isnr;
    config.guide_lag = i == 2 ? 0 : 1;
    rows[i].trainer = std::make_unique<radiosity::Trainer>(ctx, geometry, config, tmp / rows[i].name, false);
  }
  for (int i = 0; i < 5; ++i)  // warm-up: program builds, buffer growth, the GEMM probe
    for (auto& r : rows) r.trainer->step();
  ctx.finish();
  // Host stages and the device's busy time of the same blocks.
  for (auto& r : rows) r.trainer->time_host_stages(&r.host);
  for (int round = 0; round < rounds; ++round)
    for (auto& r : rows) {
      const bench::BlockTime t = bench::time_block(ctx, *r.trainer, kBlock);
      r.step_s += t.wall_s / kBlock / rounds;
      r.device_s += t.device_s;
    }
  fs::remove_all(tmp);
  const radiosity::Trainer& isnr = *rows[1].trainer;
  std::printf("%s on %s, batch %d × %d\n", scene_path.c_str(), ctx.device().describe().c_str(), isnr.config().batch,
              isnr.config().samples);
  const double t_nr = rows[0].step_s;
  for (int i = 1; i < 3; ++i)
    std::printf(
        "NR step %.1f ms, %s step %.1f ms: the I-Module's share of a step %.1f %% "
        "(target ≤ 10 %%; the paper: ≈ 10 %%)\n",
        1e3 * t_nr, rows[i].name, 1e3 * rows[i].step_s, 100 * (rows[i].step_s - t_nr) / rows[i].step_s);
  const double steps = double(rounds * kBlock);
  for (const auto& r : rows) bench::print_stages(r.name, r.host, r.device_s, r.step_s * steps);
  print_stages(ctx, nn::network_config_from_json(isnr.config().guide), std::size_t(isnr.config().batch),
               std::size_t(isnr.config().samples));
  return 0;
}
