// Reference path tracer throughput (samples/s, Mrays/s) on the Cornell box and Veach Bidir at 128×128, printed
// beside its anchor: Embree's incoherent-ray throughput (random rays through the same scene) on this machine.
// Usage: bench_reference [spp] (default 64).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "common/parallel.hpp"
#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"

namespace {

using namespace clr;

// Rays from uniform points in the scene's bounding box in uniform directions: no coherence for the BVH to exploit.
double random_ray_mrays(const geometry::Geometry& g, std::size_t count) {
  scene::Vec3 lo(1e30f), hi(-1e30f);
  for (const auto& s : g.scene().shapes)
    for (const auto& p : s.mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  std::vector<geometry::Ray> rays(count);
  Pcg32 rng(0, 1);
  for (auto& r : rays) {
    r.origin = lo + (hi - lo) * scene::Vec3(rng.next_float(), rng.next_float(), rng.next_float());
    r.direction = scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
  }
  std::vector<geometry::Hit> hits(count);
  g.intersect(rays, hits);  // warm-up
  const auto start = std::chrono::steady_clock::now();
  g.intersect(rays, hits);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return double(count) / s * 1e-6;
}

}  // namespace

int main(int argc, char** argv) {
  const int spp = argc > 1 ? std::atoi(argv[1]) : 64;
  const std::filesystem::path shared(CLR_SHARED_SCENES);
  std::printf("reference path tracer, 128x128, %d spp, %zu threads\n", spp, worker_count());
  std::printf("%-14s %12s %14s %12s   %s\n", "scene", "seconds", "Msamples/s", "Mrays/s", "anchor: Embree random rays");
  for (const char* name : {"cornell-box", "veach-bidir"}) {
    const auto file = shared / name / "scene.xml";
    if (!std::filesystem::exists(file)) {
      std::printf("%-14s (missing: %s)\n", name, file.c_str());
      continue;
    }
    const auto scene = scene::load_scene(file);
    const geometry::Geometry geometry(scene);
    reference::RenderOptions opt;
    opt.width = opt.height = 128;
    opt.spp = spp;
    reference::RenderStats stats;
    reference::render(geometry, opt, &stats);
    const double anchor = random_ray_mrays(geometry, std::size_t(1) << 21);
    std::printf("%-14s %12.2f %14.3f %12.2f   %.2f Mrays/s (path tracer at %.0f %% of it)\n", name, stats.seconds,
                double(stats.paths) / stats.seconds * 1e-6, double(stats.rays) / stats.seconds * 1e-6, anchor,
                100.0 * double(stats.rays) / stats.seconds * 1e-6 / anchor);
  }
  return 0;
}
