// The I-Module's share of an ISNR training step (the target: ≤ 10 %, the paper's overhead ≈ 10 %): NR and
// ISNR trainers with the default settings on one scene take interleaved blocks of steps; the share is
// (t_ISNR − t_NR) / t_ISNR, printed beside the anchor (the paper's ≈ 10 %, and +18 % to +38 % implied by its
// Table 1). Usage: bench_guide [SCENE.xml] [rounds] (default: the shared Cornell box, 5 rounds of 20 steps).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cl/context.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/trainer.hpp"
#include "scene/scene.hpp"

namespace {

using namespace clr;
namespace fs = std::filesystem;

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
  config.method = "nr";
  radiosity::Trainer nr(ctx, geometry, config, tmp / "nr", false);
  config.method = "isnr";
  radiosity::Trainer isnr(ctx, geometry, config, tmp / "isnr", false);
  for (int i = 0; i < 5; ++i) {  // warm-up: program builds, buffer growth, the GEMM probe
    nr.step();
    isnr.step();
  }
  ctx.finish();
  double t_nr = 0, t_isnr = 0;
  const auto time_block = [&](radiosity::Trainer& t) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kBlock; ++i) t.step();
    ctx.finish();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kBlock;
  };
  for (int r = 0; r < rounds; ++r) {
    t_nr += time_block(nr) / rounds;
    t_isnr += time_block(isnr) / rounds;
  }
  fs::remove_all(tmp);
  std::printf("%s on %s, batch %d × %d\n", scene_path.c_str(), ctx.device().describe().c_str(), nr.config().batch,
              nr.config().samples);
  std::printf(
      "NR step %.1f ms, ISNR step %.1f ms: the I-Module's share of a step %.1f %% "
      "(target ≤ 10 %%; the paper: ≈ 10 %%)\n",
      1e3 * t_nr, 1e3 * t_isnr, 100 * (t_isnr - t_nr) / t_isnr);
  return 0;
}
