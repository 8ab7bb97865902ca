// Mitsuba's `envmap` emitter: a lat-long image around the scene.
#include "common/error.hpp"
#include "scene/loader/plugin.hpp"
#include "scene/memory_budget.hpp"

namespace clr::scene::loader {
EmitterPlugin read_envmap(Context& ctx, const Props& p) {
  const auto file = ctx.file(p, "filename", "environment map");
  EmitterPlugin e;
  const float scale = p.number("scale", 1.0f);
  require_non_negative(p, "scale", Rgb(scale));
  try {
    ctx.charge_image(file, kBytesPerEnvironmentTexel);
    e.environment = std::make_unique<Environment>(Environment::envmap(file, scale, p.transform("to_world")));
  } catch (const InputError& err) {
    p.node.fail(err.what());
  }
  return e;
}
}  // namespace clr::scene::loader
