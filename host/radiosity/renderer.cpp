#include "radiosity/renderer.hpp"

#include <cstdint>
#include <map>

#include "common/parallel.hpp"

namespace clr::radiosity {

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
        const PathEnd path = trace_to_surface(geometry, {ray.origin, ray.tnear, ray.direction, ray.tfar}, rng,
                                              settings.max_delta_bounces);
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
