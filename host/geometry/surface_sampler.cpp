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
    const auto& m = shape.mesh;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const glm::uvec3 tri = m.triangles[t];
      const double a = 0.5 * double(glm::length(glm::cross(m.positions[tri.y] - m.positions[tri.x],
                                                           m.positions[tri.z] - m.positions[tri.x])));
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
      // Uniform barycentrics: (1 − √ξ1, √ξ1·ξ2) spreads ξ evenly over the triangle's area.
      const float su = std::sqrt(rng.next_float()), v = rng.next_float();
      const SurfacePoint p = surface_point(*scene_, shape_[k], prim_[k], Vec2(su * (1.0f - v), su * v));
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
