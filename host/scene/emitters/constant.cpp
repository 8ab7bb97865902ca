// Mitsuba's `constant` environment emitter.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_constant(Context&, const Props& p) {
  const Rgb radiance = p.color("radiance", Rgb(1.0f));
  if (!(radiance.x >= 0 && radiance.y >= 0 && radiance.z >= 0)) p.node.fail("radiance must be non-negative");
  EmitterPlugin e;
  e.environment = std::make_unique<Environment>(Environment::constant(radiance));
  return e;
}
}  // namespace clr::scene::loader
