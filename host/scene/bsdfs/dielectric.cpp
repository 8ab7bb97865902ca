#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/fresnel.hpp"
#include "scene/named_ior.hpp"

namespace clr::scene {
Dielectric::Dielectric(Kind kind, float eta, Texture specular_reflectance, Texture specular_transmittance,
                       std::optional<Microfacet> microfacet, std::optional<RoughnessTextures> textured)
    : kind_(kind),
      eta_(eta),
      reflectance_(std::move(specular_reflectance)),
      transmittance_(std::move(specular_transmittance)),
      mf_(microfacet),
      textured_(std::move(textured)) {}

Rgb Dielectric::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (kind_ != Kind::rough || wo.z == 0 || wi.z == 0) return Rgb(0.0f);
  const Vec3 m = half_vector(wo, wi, eta_);
  const Microfacet mf = microfacet(at);
  const float d = mf.D(m);
  if (d == 0.0f) return Rgb(0.0f);
  const float g = mf.G(wo, wi, m);
  const float co = glm::dot(wo, m), ci = glm::dot(wi, m);
  const float f = fresnel_dielectric(co, eta_).reflectance;
  if (wo.z * wi.z > 0) return reflectance_.eval(at) * (f * d * g / (4.0f * std::fabs(wo.z)));
  if (co * ci >= 0) return Rgb(0.0f);
  const float eta_rel = wo.z > 0 ? eta_ : 1.0f / eta_;
  const float denom = co + eta_rel * ci;
  return transmittance_.eval(at) * ((1.0f - f) * d * g * std::fabs(ci * co) / (std::fabs(wo.z) * denom * denom));
}

float Dielectric::pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (kind_ != Kind::rough || wo.z == 0 || wi.z == 0) return 0.0f;
  const Vec3 m = half_vector(wo, wi, eta_);
  const float co = glm::dot(wo, m), ci = glm::dot(wi, m);
  if (co * wo.z <= 0) return 0.0f;  // sample() rejects facets wo sees from behind
  const float pm = microfacet(at).pdf_m(m);
  const float f = fresnel_dielectric(co, eta_).reflectance;
  if (wo.z * wi.z > 0) return pm * f / (4.0f * std::fabs(co));
  if (co * ci >= 0) return 0.0f;
  const float eta_rel = wo.z > 0 ? eta_ : 1.0f / eta_;
  const float denom = co + eta_rel * ci;
  return pm * (1.0f - f) * eta_rel * eta_rel * std::fabs(ci) / (denom * denom);
}

std::optional<BsdfSample> Dielectric::sample_rough(const TexturePoint& at, const Vec3& wo, float u_lobe,
                                                   const Vec2& u) const {
  const Vec3 m = microfacet(at).sample_m(u);
  const float co = glm::dot(wo, m);
  if (co * wo.z <= 0) return std::nullopt;
  const auto fr = fresnel_dielectric(co, eta_);
  const bool reflection = u_lobe < fr.reflectance;
  const Vec3 wi = reflection ? reflect(wo, m) : refract(wo, m, co, fr.cos_t, fr.eta_ti);
  if ((wi.z * wo.z > 0) != reflection || wi.z == 0) return std::nullopt;
  return continuous_sample(at, wo, wi);
}

std::optional<BsdfSample> Dielectric::sample(const TexturePoint& at, const Vec3& wo, float u_lobe,
                                             const Vec2& u) const {
  if (wo.z == 0) return std::nullopt;
  if (kind_ == Kind::rough) return sample_rough(at, wo, u_lobe, u);
  if (kind_ == Kind::thin) {
    // Sum of the slab's internal bounces: R + T²R/(1−R²) = 2R/(1+R) reflected, the rest passes straight through.
    // A slab has the same medium on both sides: light meets it as from outside whichever side it comes from (|cos|;
    // the back side's inverted η would trap light behind a total internal reflection a slab cannot have).
    const float f = fresnel_dielectric(std::fabs(wo.z), eta_).reflectance;
    const float r = 2.0f * f / (1.0f + f);
    if (u_lobe < r) return BsdfSample{reflect_z(wo), reflectance_.eval(at), r, true};
    return BsdfSample{-wo, transmittance_.eval(at), 1.0f - r, true};
  }
  const auto fr = fresnel_dielectric(wo.z, eta_);
  if (u_lobe < fr.reflectance) return BsdfSample{reflect_z(wo), reflectance_.eval(at), fr.reflectance, true};
  // Radiance crossing into a denser medium is compressed into a smaller solid angle: it scales by 1/η_ti² (η_ti:
  // IOR on the light's side over the viewer's side). The rough refraction term carries the same factor.
  const Vec3 wi = refract(wo, Vec3(0, 0, 1), wo.z, fr.cos_t, fr.eta_ti);
  return BsdfSample{wi, transmittance_.eval(at) / (fr.eta_ti * fr.eta_ti), 1.0f - fr.reflectance, true};
}

}  // namespace clr::scene

namespace clr::scene::loader {
// `dielectric`, `thindielectric` and `roughdielectric`.
std::shared_ptr<const Bsdf> read_dielectric(Context& ctx, const Props& p) {
  const float eta = read_ior(p, "int_ior", 1.5046f) / read_ior(p, "ext_ior", 1.000277f);
  const std::string type = p.type();
  const auto kind = type == "dielectric"       ? Dielectric::Kind::smooth
                    : type == "thindielectric" ? Dielectric::Kind::thin
                                               : Dielectric::Kind::rough;
  if (kind != Dielectric::Kind::rough) ignore_roughness(p);
  std::optional<RoughnessTextures> textured;
  std::optional<Microfacet> mf;
  if (kind == Dielectric::Kind::rough) mf = read_rough_microfacet(ctx, p, textured);
  return std::make_shared<Dielectric>(kind, eta, ctx.texture(p, "specular_reflectance", Rgb(1.0f)),
                                      ctx.texture(p, "specular_transmittance", Rgb(1.0f)), mf, std::move(textured));
}
}  // namespace clr::scene::loader
