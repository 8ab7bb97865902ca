// Mitsuba's `constant` environment emitter.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_constant(Context&, const Props& p) {
  const Rgb radiance = p.color("radiance", Rgb(1.0f));
  require_non_negative(p, "radiance", radiance);
  EmitterPlugin e;
  e.environment = std::make_unique<Environment>(Environment::constant(radiance));
  return e;
}
}  // namespace clr::scene::loader
