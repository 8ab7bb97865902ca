// Mitsuba 3's `sdfgrid`: the zero level set of a .vol grid's trilinear interpolant in [0,1]³ (then to_world),
// meshed at load time (sdf_mesh.cpp) like every other shape.
#include "scene/loader/plugin.hpp"
#include "scene/sdf_grid.hpp"

namespace clr::scene::loader {

ShapePlugin read_sdfgrid(Context& ctx, const Props& p) {
  const auto file = ctx.file(p, "filename", "SDF grid file");
  const std::string normals = p.string("normals", "smooth");
  if (normals != "smooth" && normals != "analytic")
    p.expect("normals", {"string"}).fail("unknown normals '" + normals + "' (Mitsuba's are smooth and analytic)");
  return {mesh_sdf_grid(load_vol(file), normals == "smooth" ? SdfNormals::smooth : SdfNormals::analytic, file.string()),
          glm::mat4(1.0f)};
}

}  // namespace clr::scene::loader
