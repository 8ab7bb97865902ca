// Mitsuba's `checkerboard` texture.
#include "scene/loader/plugin.hpp"
#include "scene/textures/uv_transform.hpp"

namespace clr::scene::loader {
Texture read_checkerboard(Context&, const Props& p) {
  return Texture::checkerboard(p.color("color0", Rgb(0.4f)), p.color("color1", Rgb(0.2f)), read_uv_transform(p));
}
}  // namespace clr::scene::loader
