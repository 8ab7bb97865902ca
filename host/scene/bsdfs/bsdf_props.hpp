#pragma once
// Properties several BSDF plugins read the same way: an index of refraction (a number or a material name) and a
// microfacet distribution (Mitsuba's `distribution`, `alpha`, `alpha_u`/`alpha_v`).
#include <algorithm>

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

// The upper bound of a value that has none by nature (principledthin's eta): finite, far beyond use.
inline constexpr float kNoUpperBound = 1e3f;

// "NAME must lie in [lo, hi]" naming the value that does not, for a number and a texture's texels alike: a
// parameter outside its range is refused, never clamped, so a texture and the same constant mean the same.
void require_in_range(const Props& p, const char* name, float lo, float hi, float smallest, float largest);

// A scalar parameter that Mitsuba takes as a float or as a texture (the principled plugins): a number into
// `values.*member` (its fallback there), a texture or a <ref> to one appended to `textured`. Numbers and texels
// outside [lo, hi] are refused; a mesh attribute, whose values only its shape knows, is clamped to it at each point.
template <typename Values>
void read_value(Context& ctx, const Props& p, const char* name, float Values::*member, float lo, float hi,
                Values& values, TexturedValues<Values>& textured) {
  const Node* n = p.find(name);
  if (!n || (n->tag() != "texture" && n->tag() != "ref")) {
    values.*member = p.number(name, values.*member);
    require_in_range(p, name, lo, hi, values.*member, values.*member);
    return;
  }
  Texture t = ctx.scalar_texture(p, name, Texture());
  const Rgb smallest = t.minimum(), largest = t.maximum();
  require_in_range(p, name, lo, hi, std::min({smallest.x, smallest.y, smallest.z}),
                   t.kind() == Texture::Kind::mesh_attribute ? lo : std::max({largest.x, largest.y, largest.z}));
  if (t.is_constant())
    values.*member = t.mean_1();
  else
    textured.push_back({member, std::move(t), lo, hi});
}

}  // namespace clr::scene::loader
