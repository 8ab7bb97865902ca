#pragma once
// Next-event estimation's choice of a light: the emitting triangles and exact shapes (one among them with probability
// proportional to its power, area × luminance of radiance; a point on it uniformly by area, or, on a sphere seen from
// outside, a direction uniformly within the cone it subtends), the environment and
// each delta light (point, spot, directional, projector) take equal shares. Also gives the density of hitting a light
// by chance, for multiple importance sampling. The reference path tracer and the training's right-hand side
// (radiosity/training_batch.cpp) share it, and next_event() below, so both estimate direct light alike.
#include <vector>

#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "geometry/surface.hpp"

namespace clr::geometry {

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

// Which of the scene's lights a sampler draws. Training takes delta lights (and a sunsky's sun) by a deterministic
// sum of its own (radiosity/training_lights.hpp), so its sampler leaves them out: a share spent on them there would
// be wasted, and the environment too where its sun is taken that way (its sky is then found by directions alone).
struct LightChoice {
  bool delta = true;
  bool environment = true;
};

class LightSampler {
 public:
  explicit LightSampler(const scene::Scene& scene, LightChoice choice = {});
  bool empty() const { return cdf_.empty() && !environment_ && delta_lights_ == 0; }
  LightSample sample(const Vec3& from, Pcg32& rng) const;
  // Solid-angle density of sample() producing the point `p` of an emitting triangle or exact shape, seen from `from`.
  float pdf_triangle(const geometry::SurfacePoint& p, const Vec3& from) const;
  float pdf_environment(const Vec3& dir) const;
  // The density pdf_triangle or pdf_environment gives the end of a ray from `from` along `dir`: `hit` null where it
  // escaped.
  float pdf_hit(const SurfacePoint* hit, const Vec3& from, const Vec3& dir) const {
    return hit ? pdf_triangle(*hit, from) : pdf_environment(dir);
  }

 private:
  const scene::Scene* scene_;
  const scene::Environment* environment_;  // null where there is none or it is not drawn
  std::size_t delta_lights_;               // the scene's first delta_lights_ (all or none)
  float environment_probability_ = 0, area_probability_ = 0, delta_probability_ = 0;  // the last per light
  std::vector<std::uint32_t> shape_, prim_;
  std::vector<double> cdf_;         // cumulative power
  std::vector<float> area_;         // per light primitive (triangle or exact shape)
  std::vector<std::size_t> first_;  // per shape: index of its first light primitive (or npos)
  double total_ = 0;
};

// The power heuristic (β = 2) of a strategy of density `a` against one of density `b`.
inline float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

// One light sample's estimate of the light `p` reflects towards `wo` (f·cos·Le / p_light), weighted by the power
// heuristic against the BSDF's density of the same direction (the directions drawn beside it carry the complementary
// weight on the emission they hit). A delta light drawn counts alone (divided by its selection's probability). Counts
// the shadow ray in `rays`, if given.
Rgb next_event(const Geometry& geometry, const LightSampler& lights, const SurfacePoint& p,
               const scene::BsdfPoint& bsdf, const Vec3& wo, Pcg32& rng, std::uint64_t* rays = nullptr);

}  // namespace clr::geometry
