// Mitsuba 3's `mesh_attribute` texture: a mesh's per-vertex or per-face attribute (`name`, "vertex_…" or
// "face_…") times `scale`, evaluated where a ray hits the shape. Which shapes must carry the attribute is the
// loader's check (every shape whose material uses the texture).
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
Texture read_mesh_attribute(Context&, const Props& p) {
  if (!p.has("name")) p.node.fail("missing property 'name' (the attribute, e.g. vertex_color)");
  const std::string name = p.string("name", "");
  if (!name.starts_with("vertex_") && !name.starts_with("face_"))
    p.expect("name", {"string"}).fail("a mesh attribute's name starts with 'vertex_' or 'face_', not '" + name + "'");
  return Texture::mesh_attribute(name, p.number("scale", 1.0f), p.node.attr_or("id", p.node.where()));
}
}  // namespace clr::scene::loader
