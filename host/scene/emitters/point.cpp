// Mitsuba's `point` emitter: `intensity` (W/sr) at `position`, or at the origin of `to_world`.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_point(Context&, const Props& p) {
  if (p.has("position") && p.has("to_world")) p.node.fail("give either 'position' or 'to_world', not both");
  DeltaLight l;
  l.kind = DeltaLight::Kind::point;
  l.position = p.has("position") ? p.vector3("position", Vec3(0.0f)) : Vec3(p.transform("to_world")[3]);
  l.intensity = p.color("intensity", Rgb(1.0f));
  require_non_negative(p, "intensity", l.intensity);
  EmitterPlugin e;
  e.delta = l;
  return e;
}
}  // namespace clr::scene::loader
