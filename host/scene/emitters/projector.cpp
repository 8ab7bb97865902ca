// Mitsuba's `projector` emitter: the reciprocal of a perspective camera, projecting its `irradiance` texture (the
// irradiance on the plane z = 1 of its frame) times `scale`; its field of view is read like the camera's.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_projector(Context& ctx, const Props& p) {
  DeltaLight l;
  l.kind = DeltaLight::Kind::projector;
  if (!p.has("irradiance")) p.node.fail("missing property 'irradiance'");
  l.texture = ctx.texture(p, "irradiance", Rgb(1.0f));
  require_non_negative(p, "irradiance", *l.texture);
  l.intensity = Rgb(p.number("scale", 1.0f));
  require_non_negative(p, "scale", l.intensity);
  const glm::ivec2 size = l.texture->resolution();
  l.projection.width = size.x;
  l.projection.height = size.y;
  read_fov(p, l.projection);
  const glm::mat4 to_world = p.transform("to_world");
  l.position = Vec3(to_world[3]);
  l.to_local = glm::inverse(to_world);
  EmitterPlugin e;
  e.delta = l;
  return e;
}
}  // namespace clr::scene::loader
