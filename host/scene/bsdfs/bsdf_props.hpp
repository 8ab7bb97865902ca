#pragma once
// Properties several BSDF plugins read the same way: an index of refraction (a number or a material name) and a
// microfacet distribution (Mitsuba's `distribution`, `alpha`, `alpha_u`/`alpha_v`).
#include "scene/loader/plugin.hpp"
#include "scene/microfacet.hpp"

namespace clr::scene::loader {

float read_ior(const Props& p, const std::string& name, float fallback);
// `textured`: the alphas are textures the plugin reads itself; only the distribution is read here.
Microfacet read_microfacet(const Props& p, bool textured = false);
// A smooth plugin (conductor, plastic, dielectric) given a roughness or distribution, which Mitsuba's smooth
// plugins never read: it stays smooth, with a warning on stderr.
void ignore_roughness(const Props& p);

}  // namespace clr::scene::loader
