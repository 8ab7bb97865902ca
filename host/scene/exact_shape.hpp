#pragma once
// Mitsuba's `sphere`, `cylinder` and `disk`, kept exact: intersected and sampled as what they are, not as triangles.
// A tessellation fine enough to match Mitsuba's area and silhouette costs 262 144 triangles for a sphere (tens of MB
// with the BVH) whatever its size, so a hundred small spheres took gigabytes; and no triangle fan gives a disk
// Mitsuba's uv (r, φ/2π), which is not linear over any triangle. Exact, each costs a few words.
#include <optional>

#include "scene/frame.hpp"

namespace clr::scene {

struct ExactShape {
  // The unit shapes, in the local frame: the sphere |p| = 1; the open tube x² + y² = 1, 0 ≤ z ≤ 1; the disk
  // x² + y² ≤ 1, z = 0 (normal +z).
  enum class Kind { sphere, cylinder, disk };
  Kind kind = Kind::sphere;
  Vec3 origin{0.0f};       // the local origin in world space: the sphere's or disk's centre, the cylinder's p0
  glm::mat3 linear{1.0f};  // local → world (columns: the local axes as placed)
  bool flip = false;       // flip_normals

  // The shape `to_world` makes of the unit shape, or nullopt where Mitsuba would not model the result exactly: a
  // sphere stretched into an ellipsoid (Mitsuba refuses it), a cylinder with an elliptic or sheared section (Mitsuba
  // warns and takes the x scale as its radius). The loader tessellates those instead. A disk takes any to_world.
  static std::optional<ExactShape> from(Kind kind, const glm::mat4& to_world, bool flip);

  glm::mat4 to_world() const;  // what `from` would make this shape from
  double area() const;
  float radius() const { return glm::length(linear[0]); }  // of the sphere or cylinder
  // Mitsuba's parametrisation. Sphere: u = φ/2π, v = θ/π, θ from local +z and φ from +x towards +y. Cylinder:
  // u = φ/2π, v = z. Disk: u = r, v = φ/2π.
  Vec3 position(const Vec2& uv) const;
  Vec3 normal(const Vec2& uv) const;        // unit, world space, outwards (inwards with flip_normals)
  Vec2 uv(const glm::dvec3& offset) const;  // of the point origin + offset (world space) on or near the surface
  // ∂p/∂u and ∂p/∂v at uv (world space): the tangents that bump maps and anisotropic lobes are oriented by.
  void tangents(const Vec2& uv, Vec3& dpdu, Vec3& dpdv) const;
  // The uv of a point drawn uniformly by area from two uniforms.
  Vec2 uniform_uv(const Vec2& u) const;
  // The ray's crossings with the surface (any t), ascending; returns how many (0 to 2). In double: a ray leaving the
  // surface starts a relative 2e-5 off it (SurfacePoint::spawn_origin), so a quadric's roots are near cancellation,
  // which float would resolve to about that much.
  int crossings(const double origin[3], const double direction[3], double t[2]) const;
  // The world-space box that holds the shape (tight along each axis).
  void bounds(Vec3& lo, Vec3& hi) const;

 private:
  glm::dmat3 to_local_{1.0};       // linear's inverse
  glm::mat3 normal_matrix_{1.0f};  // its transpose: normals' map to world
};

}  // namespace clr::scene
