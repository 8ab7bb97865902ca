#include <cmath>
#include <stdexcept>

#include "scene/loader/plugin.hpp"
#include "scene/mesh.hpp"

namespace clr::scene {
namespace {
// Tessellation of the curved shapes: the sphere's relative area error is ~(π/kRings)²/6 ≈ 4e-5, the cylinder's
// (π/kSegments)²/6 ≈ 6e-6, and their normals are the exact ones, far below what a reference render at hundreds of
// spp can resolve.
constexpr int kRings = 256, kSegments = 512;
}  // namespace

Mesh make_rectangle() {
  Mesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.normals.assign(4, Vec3(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

Mesh make_cube() {
  Mesh m;
  // Six faces, each with its own four vertices so that normals stay flat.
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = side;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const auto base = std::uint32_t(m.positions.size());
      const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (const auto& c : corners) {
        Vec3 p = n;
        p[a] = c[0];
        p[b] = c[1];
        m.positions.push_back(p);
        m.normals.push_back(n);
        m.uvs.push_back({0.5f * (c[0] + 1), 0.5f * (c[1] + 1)});
      }
      // (a, b, axis) is right-handed, so counter-clockwise in (a, b) faces +axis; reverse it for the -axis face.
      if (side > 0)
        m.triangles.insert(m.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
      else
        m.triangles.insert(m.triangles.end(), {{base, base + 2, base + 1}, {base, base + 3, base + 2}});
    }
  return m;
}

namespace {

Mesh make_sphere() {
  Mesh m;
  for (int r = 0; r <= kRings; ++r) {
    const float theta = kPi * float(r) / float(kRings);
    for (int s = 0; s <= kSegments; ++s) {
      const float phi = 2.0f * kPi * float(s) / float(kSegments);
      const Vec3 p(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      m.positions.push_back(p);
      m.normals.push_back(p);
      m.uvs.push_back({phi / (2.0f * kPi), theta / kPi});
    }
  }
  const auto row = std::uint32_t(kSegments + 1);
  for (std::uint32_t r = 0; r < std::uint32_t(kRings); ++r)
    for (std::uint32_t s = 0; s < std::uint32_t(kSegments); ++s) {
      const std::uint32_t a = r * row + s, b = a + row;
      // Outward winding; the degenerate triangles at the poles are skipped.
      if (r != 0) m.triangles.push_back({a, b, a + 1});
      if (r + 1 != std::uint32_t(kRings)) m.triangles.push_back({a + 1, b, b + 1});
    }
  return m;
}

// An open tube, uv = (φ/2π, z).
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

Mesh tessellate(ExactShape::Kind kind) {
  switch (kind) {
    case ExactShape::Kind::sphere:
      return make_sphere();
    case ExactShape::Kind::cylinder:
      return make_cylinder();
    case ExactShape::Kind::disk:
      break;
  }
  throw std::logic_error("a disk is exact under every to_world that the loader accepts");
}

}  // namespace clr::scene

namespace clr::scene::loader {
ShapePlugin read_rectangle(Context&, const Props&) { return {make_rectangle(), glm::mat4(1.0f)}; }
ShapePlugin read_cube(Context&, const Props&) { return {make_cube(), glm::mat4(1.0f)}; }
ShapePlugin read_disk(Context&, const Props&) { return {Mesh{}, glm::mat4(1.0f), ExactShape::Kind::disk}; }

ShapePlugin read_sphere(Context&, const Props& p) {
  const float radius = p.number("radius", 1.0f);
  if (!(radius > 0)) p.expect("radius", {"float"}).fail("radius must be positive");
  const Vec3 center = p.vector3("center", Vec3(0.0f));
  return {Mesh{},
          glm::mat4(glm::vec4(radius, 0, 0, 0), glm::vec4(0, radius, 0, 0), glm::vec4(0, 0, radius, 0),
                    glm::vec4(center, 1)),
          ExactShape::Kind::sphere};
}
}  // namespace clr::scene::loader
