#pragma once
// Light from delta emitters (point, spot, directional, projector) reflected at a surface point: no direction
// sampled at random ever reaches them, so both the reference path tracer (one light chosen per vertex) and the
// training batch (every light, added to the right-hand side as a constant) take them by next-event estimation
// through this one function, with the same shadow ray.
#include <span>

#include "geometry/geometry.hpp"
#include "scene/delta_light.hpp"

namespace clr::geometry {

// f·cos·(arriving radiance) of `light` at `p` towards `wo`; black where the light does not reach `p`, where the BSDF
// reflects none of it, or where the shadow ray is blocked. Counts the shadow ray it traced in `rays`, if given.
Rgb reflected_delta_light(const Geometry& geometry, const SurfacePoint& p, const scene::BsdfPoint& bsdf, const Vec3& wo,
                          const scene::DeltaLight& light, std::uint64_t* rays = nullptr);

// The sum over `lights` (the training's: radiosity/training_lights.hpp).
Rgb reflected_delta_lights(const Geometry& geometry, const SurfacePoint& p, const scene::BsdfPoint& bsdf,
                           const Vec3& wo, std::span<const scene::DeltaLight> lights);

}  // namespace clr::geometry
