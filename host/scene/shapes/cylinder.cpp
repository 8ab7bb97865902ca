// Mitsuba's `cylinder`: an open tube (no caps) of `radius` from `p0` to `p1` (default: radius 1 along z from 0 to
// 1), normals facing out, uv = (φ/2π, height). Tessellated like the sphere: exact radial normals at the vertices.
#include <cmath>

#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
namespace {
constexpr int kSegments = 512;

Mesh make_cylinder() {
  Mesh m;
  for (int s = 0; s <= kSegments; ++s) {
    const float phi = 2.0f * kPi * float(s) / float(kSegments);
    const Vec3 radial(std::cos(phi), std::sin(phi), 0.0f);
    for (const float z : {0.0f, 1.0f}) {
      m.positions.push_back(radial + Vec3(0, 0, z));
      m.normals.push_back(radial);
      m.uvs.push_back({phi / (2.0f * kPi), z});
    }
  }
  for (std::uint32_t s = 0; s < std::uint32_t(kSegments); ++s) {
    const std::uint32_t a = 2 * s, b = 2 * s + 2, c = 2 * s + 3, d = 2 * s + 1;  // (φ, z): a (0,0) b (1,0) c (1,1)
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  }
  return m;
}
}  // namespace

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
  return {make_cylinder(),
          glm::mat4(glm::vec4(s * radius, 0), glm::vec4(t * radius, 0), glm::vec4(axis, 0), glm::vec4(p0, 1))};
}

}  // namespace clr::scene::loader
