#pragma once
// Next-event estimation's choice of a light: an emitting triangle with probability proportional to its power
// (area × luminance of radiance), or the environment. Also gives the density of hitting a light by chance, for
// multiple importance sampling.
#include <vector>

#include "common/pcg32.hpp"
#include "geometry/surface.hpp"

namespace clr::reference {

using geometry::Rgb;
using geometry::Vec3;

struct LightSample {
  Vec3 direction;  // unit, from the shading point towards the light
  float distance;  // infinity for the environment
  Vec3 point;      // on the light (unused for the environment)
  Vec3 light_normal;
  Rgb radiance;
  float pdf;  // solid angle at the shading point, selection included; 0: no contribution
  bool environment;
};

class LightSampler {
 public:
  explicit LightSampler(const scene::Scene& scene);
  bool empty() const { return cdf_.empty() && !scene_->environment; }
  LightSample sample(const Vec3& from, Pcg32& rng) const;
  // Solid-angle density of sample() producing the triangle point `p` seen from `from` (the hit distance t).
  float pdf_triangle(const geometry::SurfacePoint& p, const Vec3& from) const;
  float pdf_environment(const Vec3& dir) const;

 private:
  const scene::Scene* scene_;
  float environment_probability_ = 0;
  std::vector<std::uint32_t> shape_, prim_;
  std::vector<double> cdf_;         // cumulative power
  std::vector<float> area_;         // per light triangle
  std::vector<std::size_t> first_;  // per shape: index of its first light triangle (or npos)
  double total_ = 0;
};

}  // namespace clr::reference
