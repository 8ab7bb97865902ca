#include "scene/bsdfs/bsdf_props.hpp"

#include <cstdio>

#include "common/terminal_text.hpp"
#include "scene/named_ior.hpp"

namespace clr::scene::loader {

void require_in_range(const Props& p, const char* name, float lo, float hi, float smallest, float largest) {
  if (smallest >= lo && largest <= hi) return;
  const auto text = [](float v) {
    char s[32];
    std::snprintf(s, sizeof s, "%g", double(v));
    return std::string(s);
  };
  const std::string got =
      smallest == largest ? text(smallest) : "values from " + text(smallest) + " to " + text(largest);
  p.expect(name, {"float", "texture", "ref"})
      .fail(std::string(name) + " must lie in [" + text(lo) + ", " + text(hi) + "], got " + got);
}

float read_ior(const Props& p, const std::string& name, float fallback) {
  const Node* n = p.find(name);
  if (!n) return fallback;
  if (n->tag() == "string") {
    const auto v = dielectric_ior(n->attr("value"));
    if (!v) n->fail("unknown IOR name '" + n->attr("value") + "'");
    return *v;
  }
  const float v = p.number(name, fallback);
  if (!(v > 0)) n->fail("an IOR must be positive");
  return v;
}

Microfacet read_rough_microfacet(Context& ctx, const Props& p, std::optional<RoughnessTextures>& textured) {
  auto is_texture = [&](const char* name) {
    const auto it = p.named.find(name);
    return it != p.named.end() && (it->second.tag() == "texture" || it->second.tag() == "ref");
  };
  textured.reset();
  if (!(is_texture("alpha") || is_texture("alpha_u") || is_texture("alpha_v"))) return read_microfacet(p);
  if (p.has("alpha") && (p.has("alpha_u") || p.has("alpha_v")))
    p.node.fail("give either 'alpha' or 'alpha_u' and 'alpha_v', not both");
  if (p.has("alpha")) {
    const Texture a = ctx.scalar_texture(p, "alpha", Rgb(0.1f));
    textured = RoughnessTextures{a, a};
  } else {
    if (!p.has("alpha_u") || !p.has("alpha_v")) p.node.fail("give both 'alpha_u' and 'alpha_v'");
    textured =
        RoughnessTextures{ctx.scalar_texture(p, "alpha_u", Rgb(0.1f)), ctx.scalar_texture(p, "alpha_v", Rgb(0.1f))};
  }
  if (!(textured->alpha_u.mean_1() > 0 && textured->alpha_v.mean_1() > 0)) p.node.fail("alpha must be positive");
  Microfacet mf = read_microfacet(p, true);  // the distribution
  mf.alpha = textured->alpha_u.mean_1();
  mf.alpha_v = textured->alpha_v.mean_1();
  return mf;
}

Microfacet read_microfacet(const Props& p, bool textured) {
  Microfacet mf;
  const std::string d = p.string("distribution", "beckmann");
  if (d == "beckmann")
    mf.type = Microfacet::Type::beckmann;
  else if (d == "ggx")
    mf.type = Microfacet::Type::ggx;
  else
    p.expect("distribution", {"string"}).fail("unsupported distribution '" + d + "' (beckmann, ggx)");
  // Visible-normal sampling is a choice of sampling technique, not of appearance.
  p.ignore({"sample_visible"});
  if (textured) return mf;
  for (const char* name : {"alpha", "alpha_u", "alpha_v"})
    if (const Node* n = p.find(name); n && (n->tag() == "texture" || n->tag() == "ref"))
      n->fail("textured roughness is not supported by " + p.type() +
              ", as in Mitsuba 3, which takes a float there (roughconductor and roughdielectric take textures)");
  if (p.has("alpha_u") || p.has("alpha_v")) {
    if (p.has("alpha")) p.node.fail("give either 'alpha' or 'alpha_u' and 'alpha_v', not both");
    if (!p.has("alpha_u") || !p.has("alpha_v")) p.node.fail("give both 'alpha_u' and 'alpha_v'");
    mf.alpha = p.number("alpha_u", 0.1f);
    mf.alpha_v = p.number("alpha_v", 0.1f);
    if (!(mf.alpha_v >= 1e-4f)) p.node.fail("alpha_v must be at least 1e-4");
    if (mf.alpha_v == mf.alpha) mf.alpha_v = 0;
  } else {
    mf.alpha = p.number("alpha", 0.1f);
  }
  // Below 1e-4 the lobe is numerically a delta; a mirror would be the better model.
  if (!(mf.alpha >= 1e-4f)) p.node.fail("alpha must be at least 1e-4");
  return mf;
}

void ignore_roughness(const Props& p) {
  for (const char* name : {"alpha", "alpha_u", "alpha_v", "distribution"})
    if (const Node* n = p.find(name))
      std::fprintf(stderr, "%s: warning: a smooth %s BSDF ignores '%s'\n", clr::terminal_safe(n->where()).c_str(),
                   clr::terminal_safe(p.type()).c_str(), name);
}

}  // namespace clr::scene::loader
