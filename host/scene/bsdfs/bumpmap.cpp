// Mitsuba's `bumpmap`: the scene tilts the shading frame (geometry/), scattering is the nested BSDF's.
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_bumpmap(Context& ctx, const Props& p) {
  auto nested = single_nested_bsdf(ctx, p);  // first: a named <ref> to the BSDF is no height texture
  BumpMap bump;
  bump.scale = p.number("scale", 1.0f);
  const Node* height = nullptr;
  for (const auto& [name, node] : p.named)
    if (node.tag() == "texture" || (node.tag() == "ref" && !p.used.count(name))) height = &node;  // any name
  for (const Node& o : p.objects)
    if (o.tag() == "texture") height = &o;
  if (!height) p.node.fail("bumpmap needs a height texture");
  if (height->has("name")) (void)p.find(height->attr("name"));
  bump.height = ctx.texture(*height);
  return std::make_shared<BumpMapped>(bump, std::move(nested));
}
}  // namespace clr::scene::loader
