#include "scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace clr::scene {

void Mesh::transform(const glm::mat4& to_world) {
  for (auto& p : positions) p = Vec3(to_world * glm::vec4(p, 1.0f));
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(to_world)));
  for (auto& n : normals) n = glm::normalize(normal_matrix * n);
}

void Mesh::flip() {
  for (auto& t : triangles) std::swap(t.y, t.z);
  for (auto& n : normals) n = -n;
}

void Mesh::compute_vertex_normals() {
  normals.assign(positions.size(), Vec3(0.0f));
  for (const auto& t : triangles) {
    // validate() names an index out of range once the loader has the mesh whole; until then it must not be used.
    if (std::size_t(std::max({t.x, t.y, t.z})) >= positions.size()) continue;
    const Vec3 p[3] = {positions[t.x], positions[t.y], positions[t.z]};
    const Vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const float len = glm::length(n);
    if (!(len > 0)) continue;
    for (int i = 0; i < 3; ++i) {
      const Vec3 e1 = p[(i + 1) % 3] - p[i], e2 = p[(i + 2) % 3] - p[i];
      const float angle = std::acos(std::clamp(glm::dot(e1, e2) / (glm::length(e1) * glm::length(e2)), -1.0f, 1.0f));
      normals[t[i]] += n / len * angle;
    }
  }
  for (auto& n : normals) {
    const float len = glm::length(n);
    n = len > 0 ? n / len : Vec3(0, 0, 1);
  }
}

void Mesh::validate(const std::string& what) const {
  if (triangles.empty()) throw InputError(what + ": mesh has no triangles");
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i].x) || !std::isfinite(positions[i].y) || !std::isfinite(positions[i].z))
      throw InputError(what + ": vertex " + std::to_string(i) + " is not finite (NaN geometry)");
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (glm::any(glm::greaterThan(glm::abs(positions[i]), Vec3(kMaxCoordinate))))
      throw InputError(what + ": vertex " + std::to_string(i) +
                       " lies beyond ±1e12, farther than single-precision ray tracing can resolve");
  for (const auto& n : normals)
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      throw InputError(what + ": a vertex normal is not finite");
  for (const auto& uv : uvs)
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) throw InputError(what + ": a texture coordinate is not finite");
  for (const auto& t : triangles)
    if (t.x >= positions.size() || t.y >= positions.size() || t.z >= positions.size())
      throw InputError(what + ": triangle index out of range");
}

double Mesh::area() const {
  double a = 0;
  for (const auto& t : triangles)
    a += 0.5 * double(glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x])));
  return a;
}

}  // namespace clr::scene
