// Mitsuba's `normalmap`: a nested BSDF under shading normals read from a texture (geometry/ applies them).
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_normalmap(Context& ctx, const Props& p) {
  auto nested = single_nested_bsdf(ctx, p);
  if (!p.has("normalmap")) p.node.fail("missing property 'normalmap' (a texture of normals)");
  return std::make_shared<NormalMapped>(ctx.texture(p, "normalmap", Rgb(0.5f, 0.5f, 1.0f)), std::move(nested));
}
}  // namespace clr::scene::loader
