#pragma once
// Properties several BSDF plugins read the same way: an index of refraction (a number or a material name) and a
// microfacet distribution (Mitsuba's `distribution`, `alpha`, `alpha_u`/`alpha_v`).
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"
#include "scene/microfacet.hpp"

namespace clr::scene::loader {

float read_ior(const Props& p, const std::string& name, float fallback);
// `textured`: the alphas are textures the plugin reads itself; only the distribution is read here.
Microfacet read_microfacet(const Props& p, bool textured = false);
// A microfacet lobe whose alpha (or alpha_u and alpha_v) may be textures (roughconductor, roughdielectric):
// `textured` receives them where they are; the lobe returned then holds the alphas' means, which stand for it where
// one number is needed (the network's roughness input).
Microfacet read_rough_microfacet(Context& ctx, const Props& p, std::optional<RoughnessTextures>& textured);
// A smooth plugin (conductor, plastic, dielectric) given a roughness or distribution, which Mitsuba's smooth
// plugins never read: it stays smooth, with a warning on stderr.
void ignore_roughness(const Props& p);

}  // namespace clr::scene::loader
