// Mitsuba's `bitmap` texture.
#include "scene/loader/plugin.hpp"
#include "scene/textures/uv_transform.hpp"

namespace clr::scene::loader {
Texture read_bitmap(Context& ctx, const Props& p) {
  const auto file = ctx.file(p, "filename", "texture file");
  const std::string filter = p.string("filter_type", "bilinear"), wrap = p.string("wrap_mode", "repeat");
  // Mitsuba 0.x's mip-mapped filters (trilinear, ewa) blur what a pixel covers; with many samples per pixel the
  // image converges to the same picture from bilinear lookups.
  const bool smooth = filter == "bilinear" || filter == "trilinear" || filter == "ewa";
  if (!smooth && filter != "nearest")
    p.expect("filter_type", {"string"}).fail("unsupported filter_type '" + filter + "'");
  if (wrap != "repeat") p.expect("wrap_mode", {"string"}).fail("unsupported wrap_mode '" + wrap + "' (only repeat)");
  return Texture::bitmap(ctx.bitmap(file, p.boolean("raw", false)), read_uv_transform(p), smooth);
}
}  // namespace clr::scene::loader
