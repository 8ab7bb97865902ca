// Mitsuba's `directional` emitter: `irradiance` arriving along `direction` (or +z of `to_world`) everywhere.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_directional(Context&, const Props& p) {
  if (p.has("direction") && p.has("to_world")) p.node.fail("give either 'direction' or 'to_world', not both");
  DeltaLight l;
  l.kind = DeltaLight::Kind::directional;
  const Vec3 d = p.has("direction") ? p.vector3("direction", Vec3(0, 0, 1))
                                    : Vec3(p.transform("to_world") * glm::vec4(0, 0, 1, 0));
  if (!(glm::length(d) > 0)) p.node.fail("the direction is zero");
  l.direction = glm::normalize(d);
  l.intensity = p.color("irradiance", Rgb(1.0f));
  require_non_negative(p, "irradiance", l.intensity);
  EmitterPlugin e;
  e.delta = l;
  return e;
}
}  // namespace clr::scene::loader
