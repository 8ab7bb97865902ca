// Mitsuba's `thinlens` sensor: a perspective camera whose rays leave a disk of `aperture_radius` and meet at the
// plane `focus_distance` away (depth of field).
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
void read_thinlens(Context&, const Props& p, Camera& c) {
  read_fov(p, c);
  read_clip_planes(p, c);
  if (!p.has("aperture_radius")) p.node.fail("missing property 'aperture_radius'");
  c.aperture_radius = p.number("aperture_radius", 0.0f);
  if (!(c.aperture_radius > 0)) p.expect("aperture_radius", {"float"}).fail("aperture_radius must be positive");
  c.to_world = p.transform("to_world");
}
}  // namespace clr::scene::loader
