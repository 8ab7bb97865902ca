#pragma once
// Next-event estimation's choice of a light: the emitting triangles and exact shapes (one among them with probability
// proportional to its power, area × luminance of radiance; a point on it uniformly by area, or, on a sphere seen from
// outside, a direction uniformly within the cone it subtends), the environment and
// each delta light (point, spot, directional, projector) take equal shares. Also gives the density of hitting a light
// by chance, for multiple importance sampling.
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
  float pdf;  // solid angle at the shading point, selection included; 0: no contribution. Delta: the selection's
  bool environment;
  bool delta;  // a point, spot, directional or projector light: no MIS (no ray hits it)
  const scene::DeltaLight* delta_light = nullptr;  // which one, when `delta`
};

class LightSampler {
 public:
  explicit LightSampler(const scene::Scene& scene);
  bool empty() const { return cdf_.empty() && !scene_->environment && scene_->delta_lights.empty(); }
  LightSample sample(const Vec3& from, Pcg32& rng) const;
  // Solid-angle density of sample() producing the point `p` of an emitting triangle or exact shape, seen from `from`.
  float pdf_triangle(const geometry::SurfacePoint& p, const Vec3& from) const;
  float pdf_environment(const Vec3& dir) const;

 private:
  const scene::Scene* scene_;
  float environment_probability_ = 0, area_probability_ = 0, delta_probability_ = 0;  // the last per light
  std::vector<std::uint32_t> shape_, prim_;
  std::vector<double> cdf_;         // cumulative power
  std::vector<float> area_;         // per light primitive (triangle or exact shape)
  std::vector<std::size_t> first_;  // per shape: index of its first light primitive (or npos)
  double total_ = 0;
};

}  // namespace clr::reference
