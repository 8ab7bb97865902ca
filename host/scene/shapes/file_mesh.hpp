#pragma once
// What Mitsuba's mesh plugins (obj, ply, serialized) share: texture v flipped unless asked not to, and smooth
// vertex normals for meshes that come without any unless `face_normals` asks for flat shading.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {

inline ShapePlugin file_mesh(const Props& p, Mesh mesh) {
  if (!p.boolean("flip_tex_coords", true))
    for (auto& uv : mesh.uvs) uv.y = 1.0f - uv.y;
  if (p.has("max_smooth_angle")) {
    const float angle = p.number("max_smooth_angle", 0.0f);
    if (!(angle >= 0)) p.expect("max_smooth_angle", {"float"}).fail("max_smooth_angle must be non-negative");
    mesh.compute_crease_normals(angle);
  } else if (!p.boolean("face_normals", false) && mesh.normals.empty()) {
    mesh.compute_vertex_normals();
  }
  return {std::move(mesh), glm::mat4(1.0f)};
}

}  // namespace clr::scene::loader
