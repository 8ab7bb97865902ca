// Mitsuba's `cylinder`: an open tube (no caps) of `radius` from `p0` to `p1` (default: radius 1 along z from 0 to
// 1), normals facing out, uv = (φ/2π, height); exact (scene/exact_shape.hpp).
#include <cmath>

#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
ShapePlugin read_cylinder(Context&, const Props& p) {
  const float radius = p.number("radius", 1.0f);
  if (!(radius > 0)) p.expect("radius", {"float"}).fail("radius must be positive");
  const Vec3 p0 = p.vector3("p0", Vec3(0.0f)), p1 = p.vector3("p1", Vec3(0, 0, 1));
  const Vec3 axis = p1 - p0;
  const float length = glm::length(axis);
  if (!(length > 0)) p.node.fail("p0 and p1 must differ");
  // The axis' frame as Mitsuba builds it (Duff et al. 2017's orthonormal basis).
  const Vec3 n = axis / length;
  const float sign = std::copysign(1.0f, n.z), a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  const Vec3 s(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), t(b, sign + n.y * n.y * a, -n.y);
  return {Mesh{}, glm::mat4(glm::vec4(s * radius, 0), glm::vec4(t * radius, 0), glm::vec4(axis, 0), glm::vec4(p0, 1)),
          ExactShape::Kind::cylinder};
}

}  // namespace clr::scene::loader
