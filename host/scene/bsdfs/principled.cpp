// Mitsuba 3's `principled` BSDF, read from its definition (src/bsdfs/principled.cpp, principledhelpers.h): the
// lobes, their Fresnel blends and their sampling probabilities as Mitsuba weighs them, so that a scene renders as
// Mitsuba renders it.
#include <algorithm>
#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/bsdfs/principled_helpers.hpp"
#include "scene/fresnel.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {
namespace {

// The clearcoat's GTR1 ("generalised Trowbridge–Reitz", γ = 1) normal distribution, sampled by its own D·cos θm.
float gtr1_d(const Vec3& m, float alpha) {
  const float a2 = alpha * alpha, c2 = m.z * m.z;
  const float d = (a2 - 1.0f) / (kPi * std::log(a2) * (1.0f + (a2 - 1.0f) * c2));
  return d * m.z > 1e-20f ? d : 0.0f;
}
float gtr1_pdf(const Vec3& m, float alpha) { return m.z < 0 ? 0.0f : m.z * gtr1_d(m, alpha); }
Vec3 gtr1_sample(const Vec2& u, float alpha) {
  const float a2 = alpha * alpha, phi = 2.0f * kPi * u.x;
  const float c2 = (1.0f - std::pow(a2, 1.0f - u.y)) / (1.0f - a2);
  const float c = std::sqrt(std::fmax(0.0f, c2)), s = std::sqrt(std::fmax(0.0f, 1.0f - c2));
  return {std::cos(phi) * s, std::sin(phi) * s, c};
}

// The clearcoat's shadowing: a GGX G1 of roughness 0.25 for each direction (Mitsuba's clearcoat_G).
float smith_ggx1(const Vec3& v, const Vec3& m) {
  if (glm::dot(v, m) * v.z <= 0) return 0.0f;
  if (v.z == 1.0f) return 1.0f;
  const float c2 = v.z * v.z, tan2 = (1.0f - c2) / c2;
  return 2.0f / (1.0f + std::sqrt(1.0f + 0.0625f * tan2));
}

}  // namespace

Principled::Principled(Params params)
    : p_(std::move(params)),
      constant_(make_point(p_.values)),
      mean_(make_point(values_at(p_.values, p_.textured, nullptr))) {}

Principled::Point Principled::make_point(const Values& v) {
  return {v, principled_microfacet(v.roughness, v.anisotropic), 0.1f + (0.001f - 0.1f) * v.clearcoat_gloss};
}

Principled::Lobes Principled::lobes(const Point& q, float cos_o) const {
  // Mitsuba's shares: the main lobe (reflection and transmission together) its sampling rate, the clearcoat a
  // quarter of its energy, the diffuse lobe its weight; seen from inside, the main lobe alone.
  if (cos_o < 0) return q.transmission_weight() > 0 ? Lobes{1, 0, 0} : Lobes{0, 0, 0};
  Lobes l{p_.specular_rate, q.v.clearcoat != 0 ? 0.25f * q.v.clearcoat * p_.clearcoat_rate : 0.0f,
          q.reflection_weight() * p_.diffuse_rate};
  const float total = l.specular + l.clearcoat + l.diffuse;
  if (!(total > 0)) return {0, 0, 0};
  return {l.specular / total, l.clearcoat / total, l.diffuse / total};
}

// Within the main lobe, the probability of reflecting off the facet m (Fresnel factor F there): Mitsuba's shares
// of the main reflection and the transmission, 1 − w·(1 − F) and w·(1 − F) outside, F and 1 − F inside.
float Principled::reflect_probability(const Point& q, float cos_o, float f) const {
  return cos_o > 0 ? 1.0f - q.transmission_weight() * (1.0f - f) : f;
}

Rgb Principled::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z == 0 || wi.z == 0) return Rgb(0.0f);
  const bool front = wo.z > 0, reflection = wo.z * wi.z > 0;
  const Point q = point(at);
  const float bsdf = q.transmission_weight(), brdf = q.reflection_weight();
  if (!front && !(bsdf > 0)) return Rgb(0.0f);  // without transmission, black from below
  const Rgb base = p_.base_color.eval(at);
  const float lum = luminance(base);
  const Rgb tint = lum > 0 ? base / lum : Rgb(1.0f);
  const Vec3 h = half_vector(wo, wi, p_.eta);
  const float cos_oh = glm::dot(wo, h), cos_ih = glm::dot(wi, h), side = front ? 1.0f : -1.0f;
  // The facet must face wo, and wi on the side the event sends it to.
  if (!(cos_oh * side > 0) || !(cos_ih * side * (reflection ? 1.0f : -1.0f) > 0)) return Rgb(0.0f);
  const float f_dielectric = fresnel_dielectric(cos_oh, p_.eta).reflectance;
  const float metallic = q.v.metallic;
  const float d = q.spec.D(h), g = q.spec.G(wo, wi, h);
  Rgb value(0.0f);

  if (reflection && f_dielectric > 0) {
    // Outside: the dielectric's Fresnel blended with the metal's (Schlick from base_color) and the tinted share;
    // inside: the dielectric's alone, for the transmitted share.
    const Rgb f = front ? (1.0f - metallic) * (1.0f - q.v.spec_tint) * Rgb(f_dielectric) +
                              metallic * schlick(base, cos_oh, p_.eta) +
                              (1.0f - metallic) * q.v.spec_tint * schlick(tint * r0_of_eta(p_.eta), cos_oh, p_.eta)
                        : Rgb(bsdf * f_dielectric);
    value += f * (d * g / (4.0f * std::fabs(wo.z)));
  }
  if (!reflection) {
    if (!(bsdf > 0) || !(f_dielectric < 1)) return Rgb(0.0f);
    // Walter et al.'s rough transmission as Mitsuba writes it for radiance (its η² factors cancel), tinted by
    // √base_color.
    const float eta_path = front ? p_.eta : 1.0f / p_.eta, denom = cos_oh + eta_path * cos_ih;
    return glm::sqrt(base) *
           (bsdf * (1.0f - f_dielectric) * d * g * std::fabs(cos_oh * cos_ih) / (std::fabs(wo.z) * denom * denom));
  }
  if (!front) return value;
  const float cos_d = cos_ih;
  if (q.v.clearcoat > 0) {
    // Mitsuba's clearcoat: 0.25·clearcoat·F·D·G·cos θi, Schlick's F from R0 = 0.04.
    const float f = schlick(Rgb(0.04f), cos_oh, p_.eta).x;
    value +=
        Rgb(0.25f * q.v.clearcoat * f * gtr1_d(h, q.clearcoat_alpha) * smith_ggx1(wo, h) * smith_ggx1(wi, h) * wi.z);
  }
  if (brdf > 0) {
    const auto lobe =
        principled_diffuse(base, tint, q.v.roughness, q.v.flatness, q.v.sheen, q.v.sheen_tint, wo.z, wi.z, cos_d);
    value += brdf * lobe.diffuse + (1.0f - metallic) * lobe.sheen;
  }
  return value;
}

float Principled::pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z == 0 || wi.z == 0) return 0.0f;
  const Point q = point(at);
  const Lobes l = lobes(q, wo.z);
  const bool reflection = wo.z * wi.z > 0;
  const Vec3 h = half_vector(wo, wi, p_.eta);
  const float cos_oh = glm::dot(wo, h), cos_ih = glm::dot(wi, h);
  float p = 0;
  if (reflection && wo.z > 0) {
    p += l.diffuse * cosine_hemisphere_pdf(wi.z);
    if (l.clearcoat > 0) p += l.clearcoat * gtr1_pdf(h, q.clearcoat_alpha) / (4.0f * std::fabs(cos_ih));
  }
  if (l.specular > 0 && cos_oh * wo.z > 0) {  // sample() rejects facets wo sees from behind
    const float pm = l.specular * q.spec.pdf_m(h);
    const float pr = reflect_probability(q, wo.z, fresnel_dielectric(cos_oh, p_.eta).reflectance);
    if (reflection) {
      p += pm * pr / (4.0f * std::fabs(cos_oh));
    } else if (cos_oh * cos_ih < 0) {
      const float eta_path = wo.z > 0 ? p_.eta : 1.0f / p_.eta, denom = cos_oh + eta_path * cos_ih;
      p += pm * (1.0f - pr) * eta_path * eta_path * std::fabs(cos_ih) / (denom * denom);
    }
  }
  return p;
}

std::optional<BsdfSample> Principled::sample(const TexturePoint& at, const Vec3& wo, float u_lobe,
                                             const Vec2& u) const {
  if (wo.z == 0) return std::nullopt;
  const Point q = point(at);
  const Lobes l = lobes(q, wo.z);
  Vec3 wi;
  if (u_lobe < l.diffuse) {
    wi = sample_cosine_hemisphere(u);
  } else if (u_lobe < l.diffuse + l.clearcoat) {
    wi = reflect(wo, gtr1_sample(u, q.clearcoat_alpha));
    if (wi.z * wo.z <= 0) return std::nullopt;  // a reflection lobe: through the surface it is absorbed
  } else if (l.specular > 0) {
    // The rest of u_lobe, rescaled to [0, 1), chooses between reflecting off and refracting through the facet.
    const float u_event = std::fmin((u_lobe - l.diffuse - l.clearcoat) / l.specular, 0.99999994f);
    const Vec3 m = q.spec.sample_m(u);
    const float cos_om = glm::dot(wo, m);
    if (cos_om * wo.z <= 0) return std::nullopt;
    const auto fr = fresnel_dielectric(cos_om, p_.eta);
    const bool reflection = u_event < reflect_probability(q, wo.z, fr.reflectance);
    wi = reflection ? reflect(wo, m) : refract(wo, m, cos_om, fr.cos_t, fr.eta_ti);
    if ((wi.z * wo.z > 0) != reflection) return std::nullopt;
  } else {
    return std::nullopt;
  }
  if (wi.z == 0) return std::nullopt;
  return continuous_sample(at, wo, wi);
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_principled(Context& ctx, const Props& p) {
  using V = Principled::Values;
  Principled::Params q;
  // Burley's parameters, each in [0, 1] (Mitsuba takes any value; a roughness of 1e5 there gains energy).
  auto value = [&](const char* name, float V::*member) {
    read_value(ctx, p, name, member, 0.0f, 1.0f, q.values, q.textured);
  };
  value("spec_trans", &V::spec_trans);
  const bool transmits = q.values.spec_trans != 0 || is_textured(q.textured, &V::spec_trans);
  q.base_color = ctx.texture(p, "base_color", Rgb(0.5f));
  value("roughness", &V::roughness);
  value("anisotropic", &V::anisotropic);
  value("metallic", &V::metallic);
  value("spec_tint", &V::spec_tint);
  value("sheen", &V::sheen);
  value("sheen_tint", &V::sheen_tint);
  value("flatness", &V::flatness);
  value("clearcoat", &V::clearcoat);
  value("clearcoat_gloss", &V::clearcoat_gloss);
  q.specular_rate = p.number("main_specular_sampling_rate", 1.0f);
  q.clearcoat_rate = p.number("clearcoat_sampling_rate", 1.0f);
  q.diffuse_rate = p.number("diffuse_reflectance_sampling_rate", 1.0f);
  if (p.has("eta") && p.has("specular")) p.node.fail("give either 'eta' or 'specular', not both (as Mitsuba)");
  if (p.has("eta")) {
    q.eta = p.number("eta", 1.5f);
    if (!(q.eta > 0)) p.expect("eta", {"float"}).fail("eta must be positive");
    if (transmits && q.eta == 1.0f) q.eta = 1.001f;  // Mitsuba: no interface, no transmission lobe
  } else {
    // Mitsuba's one-to-one map from `specular` (R0 = 0.08·specular) to the relative IOR.
    float specular = p.number("specular", 0.5f);
    if (transmits && specular == 0.0f) specular = 1e-3f;  // Mitsuba: eta = 1 is not plausible for transmission
    if (!(specular >= 0 && specular < 12.5f)) p.expect("specular", {"float"}).fail("specular must lie in [0, 12.5)");
    q.eta = 2.0f / (1.0f - std::sqrt(0.08f * specular)) - 1.0f;
  }
  for (const float rate : {q.specular_rate, q.clearcoat_rate, q.diffuse_rate})
    if (!(rate >= 0)) p.node.fail("sampling rates must be non-negative");
  return std::make_shared<Principled>(std::move(q));
}
}  // namespace clr::scene::loader
