#pragma once
// Mitsuba's `sphere`, kept exact: intersected and sampled as a sphere, not as triangles. A tessellation fine enough
// to match Mitsuba's area and silhouette costs 262 144 triangles (tens of MB with the BVH) whatever the sphere's size,
// so a hundred small spheres took gigabytes; exact, each costs a few words.
#include <optional>

#include "scene/frame.hpp"

namespace clr::scene {

struct Sphere {
  Vec3 center{0.0f};
  float radius = 1;
  // Local axes in world space (orthonormal): uv is measured in them, as Mitsuba measures it in its to_world frame.
  glm::mat3 axes{1.0f};
  bool flip = false;  // flip_normals: normals face the centre

  // The sphere `to_world` makes of the unit sphere at the origin, or nullopt where it makes none (a non-uniform scale
  // or a shear: an ellipsoid, which the loader tessellates instead).
  static std::optional<Sphere> from(const glm::mat4& to_world, bool flip);

  glm::mat4 to_world() const;  // what `from` would make this sphere from
  double area() const;
  // Mitsuba's parametrisation: u = φ/2π, v = θ/π, with θ from the local +z axis and φ from +x towards +y.
  Vec3 direction(const Vec2& uv) const;  // unit, world space, from the centre
  Vec2 uv(const Vec3& direction) const;  // of a world-space direction from the centre (need not be unit)
  // ∂p/∂u and ∂p/∂v at uv (world space): the tangents that bump maps and anisotropic lobes are oriented by.
  void tangents(const Vec2& uv, Vec3& dpdu, Vec3& dpdv) const;
  // The uv of a point drawn uniformly by area from two uniforms.
  static Vec2 uniform_uv(const Vec2& u);
};

}  // namespace clr::scene
