// Mitsuba 3's `principledthin` BSDF, read from its definition (src/bsdfs/principledthin.cpp): a sheet with no
// inside, so both directions are first turned to the viewer's side (+z), evaluated there, and turned back.
#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/bsdfs/principled_helpers.hpp"
#include "scene/fresnel.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {

PrincipledThin::PrincipledThin(Params params)
    : p_(std::move(params)),
      constant_(make_point(p_.values)),
      mean_(make_point(values_at(p_.values, p_.textured, nullptr))) {}

PrincipledThin::Point PrincipledThin::make_point(const Values& v) {
  return {v, principled_microfacet(v.roughness, v.anisotropic),
          principled_microfacet((0.65f * v.eta - 0.35f) * v.roughness, v.anisotropic)};
}

PrincipledThin::Lobes PrincipledThin::lobes(const Point& q) const {
  const float d = 0.5f * q.v.diff_trans;  // Mitsuba reads diff_trans in [0, 2]
  Lobes l{0.5f * q.v.spec_trans * p_.specular_reflect_rate, 0.5f * q.v.spec_trans * p_.specular_trans_rate,
          (1.0f - q.v.spec_trans) * (1.0f - d) * p_.diffuse_reflect_rate,
          (1.0f - q.v.spec_trans) * d * p_.diffuse_trans_rate};
  const float total = l.spec_reflect + l.spec_trans + l.diffuse_reflect + l.diffuse_trans;
  if (!(total > 0)) return {0, 0, 0, 0};
  return {l.spec_reflect / total, l.spec_trans / total, l.diffuse_reflect / total, l.diffuse_trans / total};
}

namespace {
// The viewer's side made +z; the light's direction turned alike; its mirror image above the sheet; their half
// vector (a transmission's too: it passes as the reflection would, mirrored).
struct ThinFrame {
  Vec3 wo, wi, wi_up, h;
  bool reflection;
};
ThinFrame thin_frame(const Vec3& wo, const Vec3& wi) {
  const float s = wo.z > 0 ? 1.0f : -1.0f;
  ThinFrame t{wo * s, wi * s, wi * s, Vec3(0.0f), wi.z * s > 0};
  t.wi_up.z = std::fabs(t.wi_up.z);
  t.h = glm::normalize(t.wo + t.wi_up);
  return t;
}
}  // namespace

Rgb PrincipledThin::eval(const TexturePoint& at, const Vec3& wo_in, const Vec3& wi_in) const {
  if (wo_in.z == 0 || wi_in.z == 0) return Rgb(0.0f);
  const ThinFrame t = thin_frame(wo_in, wi_in);
  const Vec3 &wo = t.wo, &wi = t.wi, &h = t.h;
  const Rgb base = p_.base_color.eval(at);
  const Point q = point(at);
  const float diff_trans = 0.5f * q.v.diff_trans, spec_trans = q.v.spec_trans, eta = q.v.eta;
  const float cos_oh = glm::dot(wo, h), cos_ih = glm::dot(wi, h);
  Rgb value(0.0f);
  if (spec_trans > 0) {
    const float f_dielectric = fresnel_dielectric(cos_oh, eta).reflectance;
    if (t.reflection && cos_oh > 0 && cos_ih > 0) {
      // The dielectric's Fresnel blended towards Schlick's tinted by base_color's hue (Mitsuba's thin_fresnel).
      Rgb f_tinted(0.0f);
      if (q.v.spec_tint != 0) {
        const float lum = luminance(base);
        f_tinted = schlick((lum > 0 ? base / lum : Rgb(1.0f)) * r0_of_eta(eta), cos_oh, eta);
      }
      const Rgb f = Rgb(f_dielectric) + q.v.spec_tint * (f_tinted - Rgb(f_dielectric));
      value += f * (spec_trans * q.reflect.D(h) * q.reflect.G(wo, wi, h) / (4.0f * wo.z));
    }
    if (!t.reflection && cos_oh > 0 && cos_ih < 0)
      value += base * (spec_trans * (1.0f - f_dielectric) * q.transmit.D(h) * q.transmit.G(wo, wi, h) / (4.0f * wo.z));
  }
  if (t.reflection && spec_trans < 1 && diff_trans < 1) {
    const auto d = principled_diffuse(base, luminance(base) > 0 ? base / luminance(base) : Rgb(1.0f), q.v.roughness,
                                      q.v.flatness, q.v.sheen, q.v.sheen_tint, wo.z, wi.z, glm::dot(h, wi));
    value += (1.0f - spec_trans) * (1.0f - diff_trans) * (d.diffuse + d.sheen);
  }
  if (!t.reflection && spec_trans < 1 && diff_trans > 0)
    value += base * ((1.0f - spec_trans) * diff_trans * kInvPi * std::fabs(wi.z));
  return value;
}

float PrincipledThin::pdf(const TexturePoint& at, const Vec3& wo_in, const Vec3& wi_in) const {
  if (wo_in.z == 0 || wi_in.z == 0) return 0.0f;
  const ThinFrame t = thin_frame(wo_in, wi_in);
  const Point q = point(at);
  const Lobes l = lobes(q);
  const float cos_oh = glm::dot(t.wo, t.h), cos_ih = glm::dot(t.wi, t.h);
  const float jacobian = 1.0f / (4.0f * std::fabs(glm::dot(t.wi_up, t.h)));  // of the (mirrored) reflection
  if (t.reflection) {
    float p = l.diffuse_reflect * cosine_hemisphere_pdf(t.wi.z);
    if (cos_oh > 0 && cos_ih > 0) p += l.spec_reflect * q.reflect.pdf_m(t.h) * jacobian;
    return p;
  }
  float p = l.diffuse_trans * cosine_hemisphere_pdf(-t.wi.z);
  if (cos_oh > 0 && cos_ih < 0) p += l.spec_trans * q.transmit.pdf_m(t.h) * jacobian;
  return p;
}

std::optional<BsdfSample> PrincipledThin::sample(const TexturePoint& at, const Vec3& wo_in, float u_lobe,
                                                 const Vec2& u) const {
  if (wo_in.z == 0) return std::nullopt;
  const float s = wo_in.z > 0 ? 1.0f : -1.0f;
  const Vec3 wo = wo_in * s;
  const Point q = point(at);
  const Lobes l = lobes(q);
  Vec3 wi;
  if (u_lobe < l.spec_reflect + l.spec_trans) {
    const bool transmission = u_lobe >= l.spec_reflect;
    const Vec3 m = (transmission ? q.transmit : q.reflect).sample_m(u);
    wi = reflect(wo, m);
    // Facets seen from behind, and reflections through the surface, are absorbed (as pdf() assumes).
    if (glm::dot(wo, m) <= 0 || wi.z <= 0) return std::nullopt;
    if (transmission) {
      wi.z = -wi.z;  // straight through the sheet, where it must leave the facet's back (Mitsuba's check)
      if (glm::dot(wi, m) >= 0) return std::nullopt;
    }
  } else if (u_lobe < l.spec_reflect + l.spec_trans + l.diffuse_reflect) {
    wi = sample_cosine_hemisphere(u);
  } else if (l.diffuse_trans > 0) {
    wi = -sample_cosine_hemisphere(u);
  } else {
    return std::nullopt;
  }
  wi *= s;
  if (wi.z == 0) return std::nullopt;
  return continuous_sample(at, wo_in, wi);
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_principledthin(Context& ctx, const Props& p) {
  using V = PrincipledThin::Values;
  PrincipledThin::Params q;
  auto value = [&](const char* name, float V::*member, float lo = 0.0f, float hi = 1.0f) {
    read_value(ctx, p, name, member, lo, hi, q.values, q.textured);
  };
  q.base_color = ctx.texture(p, "base_color", Rgb(0.5f));
  value("roughness", &V::roughness, 0.0f, 1.0f);
  value("anisotropic", &V::anisotropic);
  value("spec_trans", &V::spec_trans);
  value("diff_trans", &V::diff_trans, 0.0f, 2.0f);
  value("spec_tint", &V::spec_tint);
  value("sheen", &V::sheen, 0.0f, 1.0f);
  value("sheen_tint", &V::sheen_tint);
  value("flatness", &V::flatness);
  value("eta", &V::eta, 1e-3f, kNoUpperBound);
  q.specular_reflect_rate = p.number("specular_reflectance_sampling_rate", 1.0f);
  q.specular_trans_rate = p.number("specular_transmittance_sampling_rate", 1.0f);
  q.diffuse_reflect_rate = p.number("diffuse_reflectance_sampling_rate", 1.0f);
  q.diffuse_trans_rate = p.number("diffuse_transmittance_sampling_rate", 1.0f);
  for (const float rate :
       {q.specular_reflect_rate, q.specular_trans_rate, q.diffuse_reflect_rate, q.diffuse_trans_rate})
    if (!(rate >= 0)) p.node.fail("sampling rates must be non-negative");
  return std::make_shared<PrincipledThin>(std::move(q));
}
}  // namespace clr::scene::loader
