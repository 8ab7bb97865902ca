// Mitsuba's `area` emitter: radiance (a colour or a texture over the surface's uv) leaving the side of a shape its
// normal faces.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_area(Context& ctx, const Props& p) {
  const Texture radiance = ctx.texture(p, "radiance", Rgb(1.0f));
  require_non_negative(p, "radiance", radiance);
  EmitterPlugin e;
  e.area = radiance;
  return e;
}
}  // namespace clr::scene::loader
