#include "radiosity/renderer.hpp"

#include <cstdint>

#include "common/parallel.hpp"

namespace clr::radiosity {

image::Image render(const geometry::Geometry& geometry, const RadianceQuery& field, const RenderSettings& settings) {
  const scene::Camera camera = geometry.scene().camera.resized(settings.width, settings.height);
  const int width = camera.width, height = camera.height;
  image::check_image_size(width, height, "--width × --height");
  const std::size_t spp = std::size_t(std::max(1, settings.spp)), R = nn::kRawInputs;
  image::Image img(width, height);

  // Chunks of at most rows_per_query camera samples, cut anywhere (not at whole lines): one line of a wide image
  // at a high spp (32768 × 65536 samples) would otherwise be a single chunk of ~170 GB. Sample s belongs to pixel
  // s / spp and draws from its own stream, so the image does not depend on the chunking.
  const std::size_t total = std::size_t(width) * std::size_t(height) * spp;
  const std::size_t chunk = std::max<std::size_t>(1, settings.rows_per_query);
  std::vector<float> rows, rgb, throughput, emitted;
  std::vector<std::int64_t> lookup;
  for (std::size_t s0 = 0; s0 < total; s0 += chunk) {
    const std::size_t n = std::min(chunk, total - s0);
    rows.assign(n * R, 0.0f);
    throughput.assign(n * 3, 0.0f);
    emitted.assign(n * 3, 0.0f);
    lookup.assign(n, -1);
    parallel_for(n, 256, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t sample = s0 + i, pixel = sample / spp;
        Pcg32 rng(sample, settings.seed);
        const float px = float(pixel % std::size_t(width)) + rng.next_float();
        const float py = float(pixel / std::size_t(width)) + rng.next_float();
        const auto ray = camera.ray(px, py);
        const PathEnd path =
            trace_to_surface(geometry, {ray.origin, ray.tnear, ray.direction}, rng, settings.max_delta_bounces);
        for (int c = 0; c < 3; ++c) {
          emitted[3 * i + c] = path.emitted[c];
          throughput[3 * i + c] = path.throughput[c];
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
      const std::size_t pixel = (s0 + i) / spp;
      float* p = img.pixel(int(pixel % std::size_t(width)), int(pixel / std::size_t(width)));
      for (int c = 0; c < 3; ++c) {
        float v = emitted[3 * i + c];
        if (lookup[i] >= 0) v += throughput[3 * i + c] * rgb[std::size_t(lookup[i]) * 3 + c];
        p[c] += v / float(spp);
      }
    }
  }
  return img;
}

}  // namespace clr::radiosity
