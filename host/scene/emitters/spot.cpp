// Mitsuba's `spot` emitter: `intensity` (W/sr) down +z of `to_world`, full within `beam_width`, falling linearly in
// angle to zero at `cutoff_angle` (degrees; default 20, beam 3/4 of it), optionally times a projected `texture`.
#include <cmath>

#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_spot(Context& ctx, const Props& p) {
  DeltaLight l;
  l.kind = DeltaLight::Kind::spot;
  const glm::mat4 to_world = p.transform("to_world");
  l.position = Vec3(to_world[3]);
  l.to_local = glm::inverse(to_world);
  l.intensity = p.color("intensity", Rgb(1.0f));
  require_non_negative(p, "intensity", l.intensity);
  const float cutoff = p.number("cutoff_angle", 20.0f), beam = p.number("beam_width", 0.75f * cutoff);
  if (!(cutoff > 0 && cutoff < 90)) p.node.fail("cutoff_angle must lie in (0, 90) degrees");
  if (!(beam >= 0 && beam <= cutoff)) p.node.fail("beam_width must lie in [0, cutoff_angle]");
  l.cutoff = cutoff * kPi / 180.0f;
  l.beam_width = beam * kPi / 180.0f;
  if (p.has("texture")) {
    l.texture = ctx.texture(p, "texture", Rgb(1.0f));
    require_non_negative(p, "texture", *l.texture);
  }
  EmitterPlugin e;
  e.delta = l;
  return e;
}
}  // namespace clr::scene::loader
