// Mitsuba's `null` BSDF: the surface does not interact with light.
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_null(Context&, const Props&) { return std::make_shared<NullBsdf>(); }
}  // namespace clr::scene::loader
