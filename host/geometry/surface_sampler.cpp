#include "geometry/surface_sampler.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "common/pcg32.hpp"

namespace clr::geometry {

SurfaceSampler::SurfaceSampler(const scene::Scene& scene) : scene_(&scene) {
  double sum = 0;
  for (std::size_t s = 0; s < scene.shapes.size(); ++s) {
    const auto& shape = scene.shapes[s];
    if (!scene.bsdf(shape).has_non_delta()) continue;
    for (std::size_t t = 0; t < shape.primitive_count(); ++t) {
      const double a = shape.primitive_area(std::uint32_t(t));
      if (!(a > 0)) continue;
      sum += a;
      shape_.push_back(std::uint32_t(s));
      prim_.push_back(std::uint32_t(t));
      cdf_.push_back(sum);
    }
  }
  total_area_ = sum;
  if (cdf_.empty()) throw InputError("the scene has no surface with a non-delta BSDF to sample");
}

void SurfaceSampler::sample(std::uint64_t seed, std::span<SurfaceSample> out, std::size_t first) const {
  parallel_for(out.size(), 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Pcg32 rng(first + i, seed);
      const double target = rng.next_double() * total_area_;
      const auto k = std::size_t(std::min<std::ptrdiff_t>(
          std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin(), std::ptrdiff_t(cdf_.size()) - 1));
      const float u0 = rng.next_float();
      const SurfacePoint p = uniform_surface_point(*scene_, shape_[k], prim_[k], Vec2(u0, rng.next_float()));
      const auto& shape = scene_->shapes[p.shape];
      const scene::Bsdf& bsdf = scene_->bsdf(shape);
      out[i] = {p, bsdf.albedo(p.at), bsdf.roughness(), std::uint32_t(shape.material)};
    }
  });
}

std::vector<SurfaceSample> SurfaceSampler::sample(std::uint64_t seed, std::size_t count) const {
  std::vector<SurfaceSample> out(count);
  sample(seed, out);
  return out;
}

}  // namespace clr::geometry
