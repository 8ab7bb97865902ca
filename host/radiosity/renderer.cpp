#include "radiosity/renderer.hpp"

#include "common/parallel.hpp"

namespace clr::radiosity {

image::Image render(const geometry::Geometry& geometry, const RadianceQuery& field, const RenderSettings& settings) {
  const scene::Camera& camera = geometry.scene().camera;
  const int width = settings.width > 0 ? settings.width : camera.width;
  const int height = settings.height > 0 ? settings.height : camera.height;
  image::check_image_size(width, height, "--width × --height");
  const std::size_t spp = std::size_t(std::max(1, settings.spp)), R = nn::kRawInputs;
  image::Image img(width, height);

  // Whole image lines per chunk, so each chunk's samples map to a contiguous block of pixels.
  const std::size_t line_samples = std::size_t(width) * spp;
  const std::size_t lines = std::max<std::size_t>(1, settings.rows_per_query / line_samples);
  std::vector<float> rows, rgb, throughput;
  std::vector<int> lookup;
  for (int y0 = 0; y0 < height; y0 += int(lines)) {
    const int y1 = std::min(height, y0 + int(lines));
    const std::size_t n = std::size_t(y1 - y0) * line_samples;
    rows.assign(n * R, 0.0f);
    throughput.assign(n * 3, 0.0f);
    lookup.assign(n, -1);
    std::vector<float> emitted(n * 3, 0.0f);
    parallel_for(n, 256, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t pixel = std::size_t(y0) * std::size_t(width) + i / spp;
        Pcg32 rng(pixel * spp + i % spp, settings.seed);
        const float px = float(pixel % std::size_t(width)) + rng.next_float();
        const float py = float(pixel / std::size_t(width)) + rng.next_float();
        // The camera's film may differ from the requested size: scale pixel coordinates to its raster.
        const auto ray = camera.ray(px * float(camera.width) / float(width), py * float(camera.height) / float(height));
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
        lookup[i] = int(k++);
      }
    rgb.assign(k * 3, 0.0f);
    if (k) field(std::span<const float>(rows.data(), k * R), rgb);
    for (std::size_t i = 0; i < n; ++i) {
      float* p = img.pixel(int((std::size_t(y0) * std::size_t(width) + i / spp) % std::size_t(width)),
                           int((std::size_t(y0) * std::size_t(width) + i / spp) / std::size_t(width)));
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
