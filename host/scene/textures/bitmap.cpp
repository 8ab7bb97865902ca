// Mitsuba's `bitmap` texture: filter_type nearest or bilinear (Mitsuba 0.x's mip-mapped trilinear and ewa read as
// bilinear), wrap_mode repeat, mirror or clamp, `raw` (no sRGB decoding) or Mitsuba 0.x's `gamma`, and Mitsuba 3's
// storage `format`.
#include "scene/loader/plugin.hpp"
#include "scene/textures/uv_transform.hpp"

namespace clr::scene::loader {
Texture read_bitmap(Context& ctx, const Props& p) {
  const auto file = ctx.file(p, "filename", "texture file");
  const std::string filter = p.string("filter_type", "bilinear"), wrap = p.string("wrap_mode", "repeat");
  // Mip-mapped filters blur what a pixel covers; with many samples per pixel the image converges to the same
  // picture from bilinear lookups.
  const bool smooth = filter == "bilinear" || filter == "trilinear" || filter == "ewa";
  if (!smooth && filter != "nearest")
    p.expect("filter_type", {"string"}).fail("unsupported filter_type '" + filter + "'");
  Bitmap::Wrap w = Bitmap::Wrap::repeat;
  if (wrap == "mirror")
    w = Bitmap::Wrap::mirror;
  else if (wrap == "clamp")
    w = Bitmap::Wrap::clamp;
  else if (wrap != "repeat")
    p.expect("wrap_mode", {"string"}).fail("unsupported wrap_mode '" + wrap + "' (repeat, mirror, clamp)");
  // Mitsuba 0.x: gamma -1 means sRGB (the default), another positive value decodes v^gamma.
  const float gamma = p.number("gamma", -1.0f);
  if (!(gamma == -1.0f || gamma > 0)) p.expect("gamma", {"float"}).fail("gamma must be positive (or -1: sRGB)");
  const std::string format = p.string("format", "auto");
  Bitmap::Storage storage = Bitmap::Storage::full;
  if (format == "float16")
    storage = Bitmap::Storage::float16;
  else if (format == "uint8")
    storage = Bitmap::Storage::uint8;
  else if (format != "auto" && format != "variant")
    p.expect("format", {"string"}).fail("unsupported format '" + format + "' (auto, variant, float16, uint8)");
  return Texture::bitmap(ctx.bitmap(file, p.boolean("raw", false), gamma, storage), read_uv_transform(p), smooth, w);
}
}  // namespace clr::scene::loader
