#pragma once
// Properties several BSDF plugins read the same way: an index of refraction (a number or a material name) and a
// microfacet distribution (Mitsuba's `distribution`, `alpha`, `alpha_u`/`alpha_v`).
#include "scene/loader/plugin.hpp"
#include "scene/microfacet.hpp"

namespace clr::scene::loader {

float read_ior(const Props& p, const std::string& name, float fallback);
Microfacet read_microfacet(const Props& p);
// A smooth plugin (conductor, plastic, dielectric) given a roughness or distribution, which Mitsuba's smooth
// plugins never read: it stays smooth, with a warning on stderr.
void ignore_roughness(const Props& p);

}  // namespace clr::scene::loader
