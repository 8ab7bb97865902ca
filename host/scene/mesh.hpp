#pragma once
// Triangle meshes: what every Mitsuba shape but the exact sphere, cylinder and disk (scene/exact_shape.hpp) becomes.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "scene/exact_shape.hpp"
#include "scene/frame.hpp"
#include "scene/texture.hpp"

namespace clr::scene {

// Mitsuba's extra per-vertex or per-face data (PLY properties beyond position, normal and uv), read by the
// `mesh_attribute` texture. The name's prefix says which: "vertex_…" (interpolated over a triangle) or "face_…"
// (constant over it).
struct MeshAttribute {
  std::string name;
  int channels = 1;           // 1 or 3 as Mitsuba evaluates them; a colour with alpha has 4 and cannot be evaluated
  std::vector<float> values;  // `channels` per vertex or per triangle

  bool per_face() const { return name.starts_with("face_"); }
  // The value at barycentrics b of triangle `prim` (vertex indices t), one channel replicated to three.
  Rgb eval(std::uint32_t prim, const glm::uvec3& t, const Vec2& b) const;
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // per vertex (shading normals); empty: flat shading with the face normal
  std::vector<Vec2> uvs;      // per vertex; empty: uv = (0, 0)
  std::vector<glm::uvec3> triangles;
  // Only those a texture of the shape's material names are kept (the loader drops the rest).
  std::vector<MeshAttribute> attributes;

  const MeshAttribute* attribute(const std::string& name) const;
  // Where textures are looked up at barycentrics b of triangle `prim`: its interpolated uv and the mesh itself.
  TexturePoint texture_point(std::uint32_t prim, const Vec2& b) const;

  void transform(const glm::mat4& to_world);
  // Reverses the winding and negates the normals (Mitsuba's flip_normals).
  void flip();
  // Angle-weighted vertex normals from the faces (Mitsuba's choice for meshes that come without normals).
  void compute_vertex_normals();
  // Mitsuba 0.x's max_smooth_angle: smooth normals only across edges whose faces meet within the angle (degrees);
  // sharper edges stay creases. Every triangle corner becomes its own vertex.
  void compute_crease_normals(float max_angle_degrees);
  // InputError (prefixed with `what`) for a triangle index beyond the vertices, normals, uvs or attributes of a
  // size other than the vertices' (or faces'), or an attribute named twice: what must hold before any index is
  // used. Every file reader calls it on its mesh before returning it.
  void check_structure(const std::string& what) const;
  // InputError (prefixed with `what`) for check_structure's faults, non-finite geometry or no triangles. Attribute
  // values are checked only where a texture reads them (the loader's keep_attributes).
  void validate(const std::string& what) const;
  double triangle_area(std::size_t i) const;
  double area() const;
};

// File formats; InputError naming the file for anything unreadable. Texture v is flipped (v' = 1 − v) as Mitsuba
// does, so images appear upright. Only PLY carries attributes (Mitsuba 3 reads none from obj or serialized files).
Mesh load_obj(const std::filesystem::path& path);
Mesh load_ply(const std::filesystem::path& path);
// `before_decoding`, where given, is told the bytes the shape's counts will cost before its data is inflated (a
// memory budget may refuse them by throwing).
Mesh load_serialized(const std::filesystem::path& path, int shape_index,
                     const std::function<void(std::uint64_t)>& before_decoding = {});

// Mitsuba's analytic shapes in their local frames: rectangle [-1,1]² in z = 0 facing +z; cube [-1,1]³ facing out.
Mesh make_rectangle();
Mesh make_cube();
// A tessellation of the unit sphere or cylinder (ExactShape's local frame), with the exact normals at its vertices:
// what stands in for an exact shape that a to_world makes into something else (an ellipsoid, an elliptic tube).
Mesh tessellate(ExactShape::Kind kind);

}  // namespace clr::scene
