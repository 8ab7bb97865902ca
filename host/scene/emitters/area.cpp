// Mitsuba's `area` emitter: radiance (a colour or a texture over the surface's uv) leaving the side of a shape its
// normal faces.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_area(Context& ctx, const Props& p) {
  const Texture radiance = ctx.texture(p, "radiance", Rgb(1.0f));
  const Rgb mean = radiance.mean();
  if (!(mean.x >= 0 && mean.y >= 0 && mean.z >= 0)) p.node.fail("radiance must be non-negative");
  EmitterPlugin e;
  e.area = radiance;
  return e;
}
}  // namespace clr::scene::loader
