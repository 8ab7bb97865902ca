// Mitsuba's `orthographic` sensor: parallel rays along +z of `to_world`, from its image of [-1, 1] × [-h/w, h/w]
// (the transform's scale sets the extent).
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
void read_orthographic(Context&, const Props& p, Camera& c) {
  c.projection = Camera::Projection::orthographic;
  read_clip_planes(p, c);
  c.to_world = p.transform("to_world");
}
}  // namespace clr::scene::loader
