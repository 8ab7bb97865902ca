// Mitsuba's `area` emitter: radiance leaving the side of a shape its normal faces.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_area(Context&, const Props& p) {
  if (p.has("radiance") && p.find("radiance")->tag() == "texture")
    p.find("radiance")->fail("textured radiance is not supported");
  const Rgb radiance = p.color("radiance", Rgb(1.0f));
  if (!(radiance.x >= 0 && radiance.y >= 0 && radiance.z >= 0)) p.node.fail("radiance must be non-negative");
  EmitterPlugin e;
  e.area = radiance;
  return e;
}
}  // namespace clr::scene::loader
