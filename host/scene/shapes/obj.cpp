#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "common/error.hpp"
#include "scene/mesh.hpp"
#include "scene/shapes/file_mesh.hpp"

namespace clr::scene {

namespace {

// tinyobjloader reads a coordinate it cannot parse ("nan", "inf", "1.0x") as 0 without a word: a corrupt file
// would render as a plausible but wrong mesh. Every number of a v/vn/vt line must be a finite number.
void check_coordinates(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string keyword, word;
    words >> keyword;
    if (keyword != "v" && keyword != "vn" && keyword != "vt") continue;
    while (words >> word && word[0] != '#') {  // a comment may end the line
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end != word.c_str() + word.size() || !std::isfinite(v))
        throw InputError(path.string() + ":" + std::to_string(number) + ": '" + keyword + "' coordinate '" + word +
                         "' is not a finite number");
    }
  }
}

// An index tinyobjloader passed on without checking (a relative index past the start, or one past the end).
void check_index(const std::filesystem::path& path, const char* what, int index, std::size_t count, bool optional) {
  if (optional && index == -1) return;
  if (index < 0 || std::size_t(index) >= count)
    throw InputError(path.string() + ": a face's " + what + " index is out of range (the file has " +
                     std::to_string(count) + ")");
}

}  // namespace

Mesh load_obj(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path.string() + ": mesh file not found");
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  check_coordinates(path);
  std::string warn, err;
  // Materials of the .mtl are Mitsuba's business (the XML assigns BSDFs): no material reader, so none is opened.
  std::ifstream in(path);
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, nullptr, true))
    throw InputError(path.string() + ": cannot read OBJ: " + err.substr(0, err.find('\n')));

  for (const auto& shape : shapes)
    for (const auto& i : shape.mesh.indices) {
      check_index(path, "vertex", i.vertex_index, attrib.vertices.size() / 3, false);
      check_index(path, "normal", i.normal_index, attrib.normals.size() / 3, true);
      check_index(path, "texture coordinate", i.texcoord_index, attrib.texcoords.size() / 2, true);
    }

  // OBJ indexes positions, normals and uvs separately; a vertex is a distinct (position, normal, uv) triple.
  struct Key {
    int v, n, t;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return std::hash<long long>()((long long)k.v * 73856093LL ^ (long long)k.n * 19349663LL ^ k.t);
    }
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> index;
  Mesh m;
  bool has_normals = !attrib.normals.empty(), has_uvs = !attrib.texcoords.empty();
  for (const auto& shape : shapes) {
    const auto& ix = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < ix.size(); f += 3) {
      glm::uvec3 tri;
      for (int c = 0; c < 3; ++c) {
        const auto& i = ix[f + std::size_t(c)];
        has_normals = has_normals && i.normal_index >= 0;
        has_uvs = has_uvs && i.texcoord_index >= 0;
        const Key key{i.vertex_index, i.normal_index, i.texcoord_index};
        auto [it, inserted] = index.try_emplace(key, std::uint32_t(m.positions.size()));
        if (inserted) {
          const auto v = std::size_t(i.vertex_index);
          m.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);
          if (i.normal_index >= 0) {
            const auto n = std::size_t(i.normal_index);
            m.normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]);
          } else {
            m.normals.emplace_back(0.0f);
          }
          if (i.texcoord_index >= 0) {
            const auto t = std::size_t(i.texcoord_index);
            m.uvs.emplace_back(attrib.texcoords[2 * t], 1.0f - attrib.texcoords[2 * t + 1]);
          } else {
            m.uvs.emplace_back(0.0f);
          }
        }
        tri[c] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  if (!has_normals) m.normals.clear();
  if (!has_uvs) m.uvs.clear();
  m.check_structure(path.string());
  return m;
}

}  // namespace clr::scene

namespace clr::scene::loader {
ShapePlugin read_obj(Context& ctx, const Props& p) {
  return file_mesh(p, load_obj(ctx.file(p, "filename", "mesh file")));
}
}  // namespace clr::scene::loader
