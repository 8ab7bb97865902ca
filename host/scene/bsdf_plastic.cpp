#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/fresnel.hpp"

namespace clr::scene {

Plastic::Plastic(float eta, Texture diffuse, Texture specular, bool nonlinear, std::optional<Microfacet> microfacet)
    : eta_(eta),
      diffuse_(std::move(diffuse)),
      specular_(std::move(specular)),
      nonlinear_(nonlinear),
      mf_(microfacet),
      fdr_int_(diffuse_fresnel_reflectance(1.0f / eta)) {
  const float s = luminance(specular_.mean()), d = luminance(diffuse_.mean());
  specular_weight_ = s + d > 0 ? s / (s + d) : 0.5f;
}

float Plastic::specular_probability(float cos_o) const {
  const float f = fresnel_dielectric(cos_o, eta_).reflectance;
  const float s = f * specular_weight_, d = (1.0f - f) * (1.0f - specular_weight_);
  return s + d > 0 ? s / (s + d) : 0.0f;
}

// The substrate: light refracts in, scatters diffusely (with repeated internal reflections off the coating) and
// refracts out; the coating's smooth Fresnel transmittance stands in for the rough one of `roughplastic` (an
// approximation: Mitsuba tabulates the rough transmittance; at the alphas of real scenes, ≤ 0.3, they differ by a
// few percent at grazing angles only).
Rgb Plastic::diffuse_term(const Vec2& uv, const Vec3& wo, const Vec3& wi) const {
  const Rgb rho = diffuse_.eval(uv);
  const Rgb substrate = nonlinear_ ? rho / (Rgb(1.0f) - rho * fdr_int_) : rho / (1.0f - fdr_int_);
  const float fo = fresnel_dielectric(wo.z, eta_).reflectance, fi = fresnel_dielectric(wi.z, eta_).reflectance;
  return substrate * ((1.0f - fi) * (1.0f - fo) / (eta_ * eta_) * kInvPi * wi.z);
}

Rgb Plastic::eval(const Vec2& uv, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  Rgb result = diffuse_term(uv, wo, wi);
  if (mf_) {
    const Vec3 m = glm::normalize(wo + wi);
    const float f = fresnel_dielectric(glm::dot(wo, m), eta_).reflectance;
    result += specular_.eval(uv) * (f * mf_->D(m) * mf_->G(wo, wi, m) / (4.0f * wo.z));
  }
  return result;
}

float Plastic::pdf(const Vec2&, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0.0f;
  const float ps = specular_probability(wo.z);
  float p = (1.0f - ps) * cosine_hemisphere_pdf(wi.z);
  if (mf_) {
    const Vec3 m = glm::normalize(wo + wi);
    p += ps * mf_->pdf_m(m) / (4.0f * glm::dot(wo, m));
  }
  return p;
}

std::optional<BsdfSample> Plastic::sample(const Vec2& uv, const Vec3& wo, float u_lobe, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  const float ps = specular_probability(wo.z);
  if (!mf_ && u_lobe < ps) {
    const float f = fresnel_dielectric(wo.z, eta_).reflectance;
    return BsdfSample{reflect_z(wo), specular_.eval(uv) * (f / ps), ps, true};
  }
  const Vec3 wi = u_lobe < ps ? reflect(wo, mf_->sample_m(u)) : sample_cosine_hemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  const float p = pdf(uv, wo, wi);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{wi, eval(uv, wo, wi) / p, p, false};
}

}  // namespace clr::scene
