#pragma once
// A point on a scene's surface, found by a ray or drawn by area: position, normals, shading frame (bump-mapped
// where the BSDF asks for it) and where textures are looked up. Independent of Embree, so the trainer and the tests can
// build one directly.
#include <cstdint>

#include "scene/scene.hpp"

namespace clr::geometry {

using scene::Rgb;
using scene::Vec2;
using scene::Vec3;

struct SurfacePoint {
  Vec3 position;
  Vec3 geometric_normal;       // unit, from the triangle's winding (an exact shape's: its normal)
  scene::Frame frame;          // shading frame: z = interpolated (and possibly bump-mapped) normal
  Vec3 untilted_normal{0.0f};  // where a bump or normal map tilted the frame, the normal before (BsdfPoint)
  scene::TexturePoint at;      // uv, and the triangle and barycentrics for mesh attributes
  std::uint32_t shape = 0, prim = 0;
  // The largest |coordinate| of the triangle's vertices (of an exact shape's box): the position and Embree's hits carry
  // float error relative to it. 0 where unknown (a point built by hand).
  float extent = 0;

  // A ray origin leaving the surface towards `dir`, pushed off the triangle's plane on the side `dir` points to,
  // by an amount relative to the coordinates' magnitude (float positions carry relative error) — never an absolute
  // one, so that a scene scaled by any factor is offset alike (tests/radiosity/extremes_test.cpp).
  Vec3 spawn_origin(const Vec3& dir) const;
  // The BSDF at this point in world space (BsdfPoint converts directions to the shading frame).
  scene::BsdfPoint bsdf(const scene::Scene& s) const { return {&s.bsdf(s.shapes[shape]), frame, at, untilted_normal}; }
};

// The point `b` of primitive `prim` of shape `shape` (scene::Shape::texture_point: a triangle's barycentrics, weights
// of vertices 1 and 2, or an exact shape's uv).
SurfacePoint surface_point(const scene::Scene& scene, std::uint32_t shape, std::uint32_t prim, const Vec2& b);
// The point of primitive `prim` that two uniforms `u` name, uniformly distributed over its area.
SurfacePoint uniform_surface_point(const scene::Scene& scene, std::uint32_t shape, std::uint32_t prim, const Vec2& u);

// Radiance the surface emits towards `wo` (world, pointing away from the surface): the area emitter's radiance on
// the side its shading normal faces, zero elsewhere and for non-emitters.
Rgb emitted(const scene::Scene& scene, const SurfacePoint& p, const Vec3& wo);

}  // namespace clr::geometry
