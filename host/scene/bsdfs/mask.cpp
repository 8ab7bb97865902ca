// Mitsuba's `mask`: the geometry cuts the holes (geometry/), scattering is the nested BSDF's.
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_mask(Context& ctx, const Props& p) {
  return std::make_shared<Mask>(ctx.scalar_texture(p, "opacity", Rgb(0.5f)), single_nested_bsdf(ctx, p));
}
}  // namespace clr::scene::loader
