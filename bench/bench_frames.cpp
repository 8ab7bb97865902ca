// Walkthrough throughput (docs/walkthrough.md): frames of a camera path rendered back to back from one model
// (radiosity::render_frames: one scene, one model, chunks of samples spanning frames) beside the same frames
// rendered one render() call each, at 128², 256², 512² and 1, 4, 16 spp. The anchor is the GEMM-bound limit: the
// network evaluations a frame needs × the MLP's FLOPs per evaluation (2 × its weights; the encoding is left out)
// ÷ the GEMM rate measured on this device at the chunk's shape — the fraction of it reached is printed.
// Usage: bench_frames [--device SPEC] [--quick] [SCENE.xml]   (default: the bundled Cornell box)
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "geometry/geometry.hpp"
#include "geometry/surface_sampler.hpp"
#include "nn/gemm.hpp"
#include "nn/network.hpp"
#include "radiosity/renderer.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "scene/scene.hpp"
#include "scene/sensors/camera_path.hpp"

using namespace clr;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
  std::string device, scene_file = std::string(CLR_SOURCE_DIR) + "/scenes/cornell-box.xml";
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--device") && i + 1 < argc)
      device = argv[++i];
    else
      scene_file = argv[i];
  }
  const auto scene = scene::load_scene(scene_file);
  const geometry::Geometry geometry(scene);
  const geometry::SurfaceSampler sampler(scene);
  cl::Context ctx(cl::select_device(device));
  // An untrained N-Module of the scene's default shape: evaluating it costs what a trained one costs.
  nn::Network network(ctx, radiosity::radiance_network_config(geometry, sampler, {}, ctx.device()));
  const auto query = radiosity::radiance_query(ctx, network);
  std::size_t evaluations = 0;
  const radiosity::RadianceQuery counted = [&](std::span<const float> rows, std::span<float> rgb) {
    evaluations += rows.size() / nn::kRawInputs;
    query(rows, rgb);
  };

  // The GEMM rate at the shape rendering runs: a chunk of rows through one hidden layer.
  const std::size_t rows = radiosity::RenderSettings{}.rows_per_query, w = network.config().width;
  cl::Buffer<float> a(ctx, rows * w), b(ctx, w * w), c(ctx, rows * w);
  nn::Gemm gemm(ctx);
  const auto product = [&] {
    gemm.run(nn::Op::N, nn::Op::N, rows, w, w, 1.0f, nn::mat(a, w), nn::mat(b, w), 0.0f, nn::mat(c, w));
    ctx.finish();
  };
  product();
  double best = 1e30;
  for (int i = 0; i < 5; ++i) {
    const auto t0 = Clock::now();
    product();
    best = std::min(best, seconds_since(t0));
  }
  const double gemm_flops = 2.0 * double(rows) * double(w) * double(w) / best;
  const double flops_per_eval = 2.0 * double(nn::mlp_parameter_count(network.config()));
  std::printf(
      "bench_frames: %s on %s; MLP width %zu, %.0f FLOPs per evaluation; GEMM %zu×%zu·%zu×%zu at %.1f GFLOP/s "
      "(%s)\n",
      scene_file.c_str(), ctx.device().describe().c_str(), w, flops_per_eval, rows, w, w, w, gemm_flops * 1e-9,
      nn::to_string(gemm.plan()).c_str());
  std::printf("%-6s %4s %7s | %12s %12s %8s | %14s %9s\n", "size", "spp", "frames", "single ms/fr", "batch ms/fr",
              "speedup", "GEMM-bound ms", "fraction");

  const std::vector<int> sizes = quick ? std::vector<int>{128} : std::vector<int>{128, 256, 512};
  const std::vector<int> spps = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 16};
  for (const int size : sizes)
    for (const int spp : spps) {
      // Fewer frames where each is large: every row takes seconds, not minutes, on a 2-core CPU.
      const int frames = std::max(2, int(std::min<long>(16, (long(1) << 21) / (long(size) * size * spp))));
      const auto cameras = scene::orbit(scene.camera, scene::geometry_centre(scene.shapes), frames);
      radiosity::RenderSettings settings;
      settings.width = settings.height = size;
      settings.spp = spp;
      // Best of three, the two ways alternating: the machine's other load hits both alike.
      double single = 1e30, batch = 1e30;
      for (int rep = 0; rep < 3; ++rep) {
        auto t0 = Clock::now();
        for (const auto& camera : cameras)
          radiosity::render_frames(geometry, std::span(&camera, 1), query, settings,
                                   [](std::size_t, image::Image&&) {});
        single = std::min(single, seconds_since(t0) / frames);
        evaluations = 0;
        t0 = Clock::now();
        radiosity::render_frames(geometry, cameras, counted, settings, [](std::size_t, image::Image&&) {});
        batch = std::min(batch, seconds_since(t0) / frames);
      }
      const double bound = double(evaluations) / frames * flops_per_eval / gemm_flops;
      std::printf("%4d²  %4d %7d | %12.2f %12.2f %7.2fx | %14.2f %8.1f%%\n", size, spp, frames, single * 1e3,
                  batch * 1e3, single / batch, bound * 1e3, 100.0 * bound / batch);
      std::fflush(stdout);
    }
  return 0;
}
