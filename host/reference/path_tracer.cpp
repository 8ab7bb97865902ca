#include "reference/path_tracer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <vector>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "common/pcg32.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "geometry/light_sampler.hpp"

namespace clr::reference {
namespace {

using scene::Rgb;
using scene::Vec2;
using scene::Vec3;

// Russian roulette starts after this many bounces unless the scene's integrator names its rr_depth: short paths
// carry most of the image and stay noise-free.
constexpr int kRouletteDepth = 3;

class PathTracer {
 public:
  PathTracer(const geometry::Geometry& g, int max_depth)
      : g_(g),
        s_(g.scene()),
        lights_(s_),
        max_depth_(max_depth),
        roulette_depth_(s_.rr_depth.value_or(kRouletteDepth)) {}

  Rgb radiance(geometry::Ray ray, Pcg32& rng, std::uint64_t& rays) const {
    Rgb L(0.0f), beta(1.0f);
    bool specular = true;  // the last bounce was a delta lobe (or there was none): no MIS on what it hits
    float prev_pdf = 0;
    Vec3 prev_position(0.0f);
    for (int depth = 0;; ++depth) {
      ++rays;
      const geometry::Hit hit = g_.intersect(ray);
      if (!hit.valid()) {
        if (s_.environment) {
          const float w = specular ? 1.0f : geometry::power_heuristic(prev_pdf, lights_.pdf_environment(ray.direction));
          L += beta * s_.environment->eval(ray.direction) * w;
        }
        break;
      }
      const geometry::SurfacePoint sp = g_.surface(hit);
      const Vec3 wo = -ray.direction;
      if (const Rgb le = geometry::emitted(s_, sp, wo); !scene::is_black(le)) {
        const float w = specular ? 1.0f : geometry::power_heuristic(prev_pdf, lights_.pdf_triangle(sp, prev_position));
        L += beta * le * w;
      }
      if (max_depth_ >= 0 && depth + 1 >= max_depth_) break;

      const scene::BsdfPoint bsdf = sp.bsdf(s_);
      if (bsdf.bsdf->has_non_delta() && !lights_.empty())
        L += beta * geometry::next_event(g_, lights_, sp, bsdf, wo, rng, &rays);

      const auto bs = bsdf.sample(wo, rng.next_float(), Vec2(rng.next_float(), rng.next_float()));
      if (!bs) break;
      beta *= bs->weight;
      specular = bs->delta;
      prev_pdf = bs->pdf;
      prev_position = sp.position;
      ray = {sp.spawn_origin(bs->wi), 0.0f, bs->wi};
      if (scene::is_black(beta)) break;
      if (depth + 1 >= roulette_depth_) {
        const float q = std::fmin(scene::max_component(beta), 0.95f);
        if (rng.next_float() >= q) break;
        beta /= q;
      }
    }
    return L;
  }

 private:
  const geometry::Geometry& g_;
  const scene::Scene& s_;
  geometry::LightSampler lights_;
  int max_depth_, roulette_depth_;
};

}  // namespace

image::Image render(const geometry::Geometry& geometry, const RenderOptions& options, RenderStats* stats) {
  const scene::Camera camera = options.camera.value_or(geometry.scene().camera).resized(options.width, options.height);
  image::check_image_size(camera.width, camera.height, "--width × --height");
  const PathTracer tracer(geometry, options.max_depth.value_or(geometry.scene().max_depth));
  const auto width = std::size_t(camera.width);
  const auto stride = std::size_t(std::max(1, options.row_stride)),
             offset = std::size_t(std::max(0, options.row_offset));
  const std::size_t rows =
      offset < std::size_t(camera.height) ? (std::size_t(camera.height) - offset - 1) / stride + 1 : 0;
  // A pass draws `per_pass` samples of every pixel, back to back (they trace alike, which keeps caches and branch
  // predictors warm), and ~2^22 samples in all (a second or two on a few cores) so that its start and end cost nothing;
  // from the whole image's size, never a rank's share, so that every rank groups the sums alike.
  const int per_pass = int(std::clamp<std::size_t>((std::size_t(1) << 22) / (width * std::size_t(camera.height)), 1,
                                                   std::size_t(std::max(1, options.spp))));
  // The sums of the finished passes, and those of the pass under way, added to them only once it is whole.
  std::vector<glm::dvec3> sum(rows * width, glm::dvec3(0.0)), pass(rows * width);
  std::atomic<std::uint64_t> rays{0};
  std::uint64_t non_finite = 0;
  std::atomic<std::size_t> row_samples{0};  // rows × samples traced, for the progress line
  std::mutex progress_mutex;
  std::optional<Progress> progress;
  if (options.progress)
    progress.emplace("reference", double(rows) * double(options.first_sample + options.spp), 5.0,
                     double(rows) * double(options.first_sample));
  const auto start = std::chrono::steady_clock::now();

  int spp = 0;  // in `sum`
  while (spp < options.spp) {
    const int first = options.first_sample + spp, count = std::min(per_pass, options.spp - spp);
    std::atomic<bool> cut{false};
    std::atomic<std::uint64_t> bad{0};
    parallel_for(rows, 1, [&](std::size_t i0, std::size_t i1) {
      std::uint64_t local_rays = 0, local_bad = 0;
      for (std::size_t i = i0; i < i1 && !cut; ++i) {
        const std::size_t y = offset + i * stride;
        for (std::size_t x = 0; x < width; ++x) {
          if (options.stoppable && stop_requested()) {
            cut = true;
            break;
          }
          glm::dvec3 pixel_sum(0.0);
          for (int s = first; s < first + count; ++s) {
            Pcg32 rng = Pcg32::for_sample(y * width + x, std::uint64_t(s), options.seed);
            const auto ps = camera.pixel_sample(x, y, rng);
            // A thin lens draws its aperture point; pinholes draw nothing more.
            const scene::Vec2 lens =
                camera.aperture_radius > 0 ? scene::Vec2(rng.next_float(), rng.next_float()) : scene::Vec2(0.5f);
            const auto cr = camera.ray(ps.px, ps.py, lens);
            const Rgb L = tracer.radiance({cr.origin, cr.tnear, cr.direction, cr.tfar}, rng, local_rays) * ps.weight;
            if (std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z))
              pixel_sum += glm::dvec3(L);
            else
              ++local_bad;
          }
          pass[i * width + x] = pixel_sum;
        }
        const std::size_t done = row_samples += std::size_t(count);
        if (progress) {
          std::lock_guard lock(progress_mutex);
          progress->update(double(rows) * double(options.first_sample) + double(done));
        }
      }
      rays += local_rays;
      bad += local_bad;
    });
    if (cut) break;
    parallel_for(sum.size(), std::size_t(1) << 16, [&](std::size_t p0, std::size_t p1) {
      for (std::size_t p = p0; p < p1; ++p) sum[p] += pass[p];
    });
    non_finite += bad;
    spp += count;
    if (options.between_passes) options.between_passes();
  }
  if (progress) progress->finish();

  image::Image img(camera.width, camera.height);
  for (std::size_t i = 0; i < rows && spp > 0; ++i)
    for (std::size_t x = 0; x < width; ++x) {
      const glm::dvec3 mean = sum[i * width + x] / double(spp);
      float* p = img.pixel(int(x), int(offset + i * stride));
      p[0] = float(mean.x);
      p[1] = float(mean.y);
      p[2] = float(mean.z);
    }
  if (stats) {
    stats->spp = spp;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->paths = std::uint64_t(width) * std::uint64_t(rows) * std::uint64_t(spp);
    stats->rays = rays;
    stats->non_finite = non_finite;
  }
  return img;
}

int samples_per_pixel(const scene::Scene& scene, const std::string& path, int given, const std::string& option) {
  const auto in_range = [](long long spp) { return spp >= 1 && spp <= (1 << 24); };
  if (given != 0) {
    if (!in_range(given)) throw InputError(option + ": " + std::to_string(given) + " is not in [1, 2^24]");
    return given;
  }
  if (!scene.sample_count)
    throw InputError(option + ": give the samples per pixel; " + path +
                     " names none (<sampler><integer name=\"sample_count\">)");
  if (!in_range(*scene.sample_count))
    throw InputError(option + ": give the samples per pixel; " + path + "'s sampler asks for " +
                     std::to_string(*scene.sample_count) + ", outside [1, 2^24]");
  return *scene.sample_count;
}

}  // namespace clr::reference
