#include "radiosity/renderer.hpp"

#include <cstdint>
#include <map>

#include "common/parallel.hpp"
#include "geometry/delta_lighting.hpp"
#include "radiosity/training_lights.hpp"

namespace clr::radiosity {
namespace {

// Replaces the end of `path` at the modelled surface x by one sample of x's right-hand side: the direct term added
// to path.emitted, and the BSDF-sampled direction followed to the next modelled surface, whose emission takes the
// MIS weight training gives it (training_batch.cpp) and whose lookup becomes path's.
void one_bounce(const geometry::Geometry& geometry, std::span<const scene::DeltaLight> deltas,
                const geometry::LightSampler& lights, bool sun, int max_delta_bounces, Pcg32& rng, PathEnd& path) {
  const geometry::SurfacePoint x = path.point;
  const Vec3 wo = path.wo;
  const scene::BsdfPoint bsdf = x.bsdf(geometry.scene());
  Rgb direct(0.0f);
  if (!deltas.empty()) direct += geometry::reflected_delta_lights(geometry, x, bsdf, wo, deltas);
  if (!lights.empty()) direct += geometry::next_event(geometry, lights, x, bsdf, wo, rng);
  path.emitted += path.throughput * direct;
  path.at_surface = false;
  const float u_lobe = rng.next_float();
  const auto bs = bsdf.sample(wo, u_lobe, {rng.next_float(), rng.next_float()});
  if (!bs) return;
  PathEnd next =
      trace_to_surface(geometry, {x.spawn_origin(bs->wi), 0.0f, bs->wi}, rng, max_delta_bounces, bs->delta || !sun);
  if (!lights.empty() && !bs->delta && !scene::is_black(next.first_emitted)) {
    const float p_light = lights.pdf_hit(next.first_hit ? &*next.first_hit : nullptr, x.position, bs->wi);
    next.emitted -= next.first_emitted * (1.0f - geometry::power_heuristic(bs->pdf, p_light));
  }
  const Rgb throughput = path.throughput * bs->weight;
  path.emitted += throughput * next.emitted;
  path.throughput = throughput * next.throughput;
  path.at_surface = next.at_surface;
  path.point = next.point;
  path.wo = next.wo;
}

}  // namespace

image::Image render(const geometry::Geometry& geometry, const RadianceQuery& field, const RenderSettings& settings) {
  image::Image out;
  const scene::Camera camera = geometry.scene().camera;
  render_frames(geometry, std::span(&camera, 1), field, settings,
                [&](std::size_t, image::Image&& img) { out = std::move(img); });
  return out;
}

void render_frames(const geometry::Geometry& geometry, std::span<const scene::Camera> cameras,
                   const RadianceQuery& field, const RenderSettings& settings,
                   const std::function<void(std::size_t, image::Image&&)>& done, const std::function<bool()>& stop) {
  if (cameras.empty()) return;
  std::vector<scene::Camera> views;
  for (const auto& c : cameras) views.push_back(c.resized(settings.width, settings.height));
  const int width = views.front().width, height = views.front().height;
  image::check_image_size(width, height, "--width × --height");
  const std::size_t spp = std::size_t(std::max(1, settings.spp)), R = nn::kRawInputs;
  const std::size_t per_frame = std::size_t(width) * std::size_t(height) * spp;

  // Chunks of at most rows_per_query camera samples, cut anywhere (not at whole lines or frames): one line of a
  // wide image at a high spp (32768 × 65536 samples) would otherwise be a single chunk of ~170 GB, and a 128² frame
  // at 1 spp alone would fill a quarter of one. Sample s of a frame draws from stream s, so an image depends neither
  // on the chunking nor on the frames beside it.
  const std::size_t total = per_frame * views.size();
  const std::size_t chunk = std::max<std::size_t>(1, settings.rows_per_query);
  // The right-hand side's direct term: training's lights (radiosity/training_lights.hpp), so that the image's
  // estimator is the one the model was trained to match.
  const bool rhs = settings.mode == RenderMode::rhs;
  const scene::Scene& scene = geometry.scene();
  const std::vector<scene::DeltaLight> deltas = rhs ? training_delta_lights(scene) : std::vector<scene::DeltaLight>{};
  const std::optional<geometry::LightSampler> lights =
      rhs ? std::optional(training_light_sampler(scene)) : std::nullopt;
  const bool sun = scene.environment && scene.environment->sun_as_directional();
  std::map<std::size_t, image::Image> open;  // frames with samples in, not yet complete
  std::vector<float> rows, rgb, throughput, emitted;
  std::vector<std::int64_t> lookup;
  for (std::size_t s0 = 0; s0 < total; s0 += chunk) {
    if (stop && stop()) return;
    const std::size_t n = std::min(chunk, total - s0);
    rows.assign(n * R, 0.0f);
    throughput.assign(n * 3, 0.0f);
    emitted.assign(n * 3, 0.0f);
    lookup.assign(n, -1);
    parallel_for(n, 256, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t frame = (s0 + i) / per_frame, sample = (s0 + i) % per_frame, pixel = sample / spp;
        Pcg32 rng(sample, settings.seed);
        const scene::Camera& view = views[frame];
        const auto ps = view.pixel_sample(pixel % std::size_t(width), pixel / std::size_t(width), rng);
        // A thin lens draws its aperture point, as the path tracer does; pinholes draw nothing more.
        const scene::Vec2 lens =
            view.aperture_radius > 0 ? scene::Vec2(rng.next_float(), rng.next_float()) : scene::Vec2(0.5f);
        const auto ray = view.ray(ps.px, ps.py, lens);
        PathEnd path = trace_to_surface(geometry, {ray.origin, ray.tnear, ray.direction, ray.tfar}, rng,
                                        settings.max_delta_bounces);
        if (rhs && path.at_surface) one_bounce(geometry, deltas, *lights, sun, settings.max_delta_bounces, rng, path);
        for (int c = 0; c < 3; ++c) {
          emitted[3 * i + c] = path.emitted[c] * ps.weight;
          throughput[3 * i + c] = path.throughput[c] * ps.weight;
        }
        if (path.at_surface) {
          write_raw_row(geometry.scene(), path.point, path.wo, &rows[i * R]);
          lookup[i] = 1;
        }
      }
    });
    // Compact the lookups, query the field once for the chunk, then accumulate per pixel.
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (lookup[i] >= 0) {
        std::copy_n(&rows[i * R], R, &rows[k * R]);
        lookup[i] = std::int64_t(k++);
      }
    rgb.assign(k * 3, 0.0f);
    if (k) field(std::span<const float>(rows.data(), k * R), rgb);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t frame = (s0 + i) / per_frame, pixel = (s0 + i) % per_frame / spp;
      auto it = open.find(frame);
      if (it == open.end()) it = open.emplace(frame, image::Image(width, height)).first;
      float* p = it->second.pixel(int(pixel % std::size_t(width)), int(pixel / std::size_t(width)));
      for (int c = 0; c < 3; ++c) {
        float v = emitted[3 * i + c];
        if (lookup[i] >= 0) v += throughput[3 * i + c] * rgb[std::size_t(lookup[i]) * 3 + c];
        p[c] += v / float(spp);
      }
    }
    // Frames whose last sample was in this chunk are complete.
    while (!open.empty() && (open.begin()->first + 1) * per_frame <= s0 + n) {
      done(open.begin()->first, std::move(open.begin()->second));
      open.erase(open.begin());
    }
  }
}

}  // namespace clr::radiosity
