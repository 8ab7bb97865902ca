#include "scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "common/error.hpp"

namespace clr::scene {

Rgb MeshAttribute::eval(std::uint32_t prim, const glm::uvec3& t, const Vec2& b) const {
  const auto c = std::size_t(channels);
  auto at = [&](std::size_t element) {
    const float* v = &values[element * c];
    return c == 1 ? Rgb(v[0]) : Rgb(v[0], v[1], v[2]);
  };
  if (per_face()) return at(prim);
  return (1.0f - b.x - b.y) * at(t.x) + b.x * at(t.y) + b.y * at(t.z);
}

const MeshAttribute* Mesh::attribute(const std::string& name) const {
  for (const auto& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

TexturePoint Mesh::texture_point(std::uint32_t prim, const Vec2& b) const {
  const glm::uvec3 t = triangles[prim];
  const Vec2 uv = uvs.empty() ? Vec2(0.0f) : (1.0f - b.x - b.y) * uvs[t.x] + b.x * uvs[t.y] + b.y * uvs[t.z];
  return {uv, *this, prim, b};
}

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
    // The file readers refuse an index out of range (check_structure); a mesh built in code may still hold one.
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

void Mesh::compute_crease_normals(float max_angle_degrees) {
  // Every index below is used unchecked: the corners' positions, uvs and attributes are copied by it.
  check_structure("mesh");
  // Corners at the same position share a normal across an edge only when their faces' normals lie within the
  // angle; every corner becomes its own vertex (uvs kept) holding the angle-weighted mean of those faces.
  const std::size_t nt = triangles.size();
  std::vector<Vec3> face(nt, Vec3(0.0f));
  std::vector<Vec3> corner_weight(nt, Vec3(0.0f));  // the angle at each corner
  for (std::size_t f = 0; f < nt; ++f) {
    const auto& t = triangles[f];
    const Vec3 p[3] = {positions[t.x], positions[t.y], positions[t.z]};
    const Vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const float len = glm::length(n);
    if (!(len > 0)) continue;
    face[f] = n / len;
    for (int i = 0; i < 3; ++i) {
      const Vec3 e1 = p[(i + 1) % 3] - p[i], e2 = p[(i + 2) % 3] - p[i];
      corner_weight[f][i] = std::acos(std::clamp(glm::dot(e1, e2) / (glm::length(e1) * glm::length(e2)), -1.0f, 1.0f));
    }
  }
  // Corners grouped by exact position (vertices a file duplicated for their uvs meet here again), and within a
  // position by exact face normal, their angles summed: every corner is then compared with the distinct normals
  // around it, not with every corner there, so a fan of many coplanar faces about one vertex costs its size, not
  // its square.
  using Key = std::tuple<float, float, float>;
  struct Normals {
    std::vector<std::pair<Vec3, float>> weighted;  // distinct face normal → summed corner angle
    std::map<Key, std::size_t> index;              // face normal → its place in `weighted`
  };
  std::map<Key, Normals> at;  // position → the normals of the faces meeting there
  for (std::size_t f = 0; f < nt; ++f)
    for (int i = 0; i < 3; ++i) {
      const Vec3 q = positions[triangles[f][i]];
      Normals& here = at[{q.x, q.y, q.z}];
      const auto [slot, added] = here.index.try_emplace({face[f].x, face[f].y, face[f].z}, here.weighted.size());
      if (added) here.weighted.emplace_back(face[f], 0.0f);
      here.weighted[slot->second].second += corner_weight[f][i];
    }
  const float cos_max = std::cos(max_angle_degrees * kPi / 180.0f);
  Mesh out;
  out.positions.resize(3 * nt);
  out.normals.resize(3 * nt);
  if (!uvs.empty()) out.uvs.resize(3 * nt);
  out.triangles.resize(nt);
  out.attributes = attributes;
  for (auto& a : out.attributes)
    if (!a.per_face()) a.values.resize(3 * nt * std::size_t(a.channels));
  for (std::size_t f = 0; f < nt; ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = triangles[f][i], c = std::uint32_t(3 * f + std::size_t(i));
      out.positions[c] = positions[v];
      if (!uvs.empty()) out.uvs[c] = uvs[v];
      for (std::size_t k = 0; k < attributes.size(); ++k)
        if (!attributes[k].per_face()) {
          const auto n = std::size_t(attributes[k].channels);
          std::copy_n(&attributes[k].values[v * n], n, &out.attributes[k].values[c * n]);
        }
      out.triangles[f][i] = c;
      Vec3 sum(0.0f);
      for (const auto& [normal, weight] : at[{positions[v].x, positions[v].y, positions[v].z}].weighted)
        if (glm::dot(normal, face[f]) >= cos_max) sum += normal * weight;
      const float len = glm::length(sum);
      out.normals[c] = len > 0 ? sum / len : (glm::length(face[f]) > 0 ? face[f] : Vec3(0, 0, 1));
    }
  *this = std::move(out);
}

void Mesh::check_structure(const std::string& what) const {
  const std::size_t n = positions.size();
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (triangles[i][c] >= n)
        throw InputError(what + ": triangle " + std::to_string(i) + " has vertex index " +
                         std::to_string(triangles[i][c]) + ": index out of range (the mesh has " + std::to_string(n) +
                         " vertices)");
  if (!normals.empty() && normals.size() != n)
    throw InputError(what + ": " + std::to_string(normals.size()) + " vertex normals for " + std::to_string(n) +
                     " vertices");
  if (!uvs.empty() && uvs.size() != n)
    throw InputError(what + ": " + std::to_string(uvs.size()) + " texture coordinates for " + std::to_string(n) +
                     " vertices");
  for (const auto& a : attributes) {
    const std::size_t elements = a.per_face() ? triangles.size() : n;
    if (a.channels < 1 || a.values.size() != elements * std::size_t(a.channels))
      throw InputError(what + ": mesh attribute '" + a.name + "' holds " + std::to_string(a.values.size()) +
                       " values, not " + std::to_string(a.channels) + " for each of the " + std::to_string(elements) +
                       (a.per_face() ? " faces" : " vertices"));
  }
  for (std::size_t i = 0; i < attributes.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (attributes[i].name == attributes[j].name)
        throw InputError(what + ": mesh attribute '" + attributes[i].name + "' is defined twice");
}

void Mesh::validate(const std::string& what) const {
  if (triangles.empty()) throw InputError(what + ": mesh has no triangles");
  check_structure(what);
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
}

double Mesh::triangle_area(std::size_t i) const {
  const glm::uvec3 t = triangles[i];
  return 0.5 * double(glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x])));
}

double Mesh::area() const {
  double a = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i) a += triangle_area(i);
  return a;
}

}  // namespace clr::scene
