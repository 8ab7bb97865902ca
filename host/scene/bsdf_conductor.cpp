#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/fresnel.hpp"

namespace clr::scene {

Rgb Conductor::eval(const Vec2& uv, const Vec3& wo, const Vec3& wi) const {
  if (!mf_ || wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  const Vec3 m = glm::normalize(wo + wi);
  const float d = mf_->D(m);
  if (d == 0.0f) return Rgb(0.0f);
  const Rgb f = fresnel_conductor(glm::dot(wo, m), eta_, k_);
  return specular_.eval(uv) * f * (d * mf_->G(wo, wi, m) / (4.0f * wo.z));
}

float Conductor::pdf(const Vec2&, const Vec3& wo, const Vec3& wi) const {
  if (!mf_ || wo.z <= 0 || wi.z <= 0) return 0.0f;
  const Vec3 m = glm::normalize(wo + wi);
  return mf_->pdf_m(m) / (4.0f * glm::dot(wo, m));
}

std::optional<BsdfSample> Conductor::sample(const Vec2& uv, const Vec3& wo, float, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  if (!mf_) return BsdfSample{reflect_z(wo), specular_.eval(uv) * fresnel_conductor(wo.z, eta_, k_), 1.0f, true};
  const Vec3 wi = reflect(wo, mf_->sample_m(u));
  if (wi.z <= 0) return std::nullopt;
  const float p = pdf(uv, wo, wi);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{wi, eval(uv, wo, wi) / p, p, false};
}

Rgb Conductor::albedo(const Vec2& uv) const { return specular_.eval(uv) * fresnel_conductor(1.0f, eta_, k_); }

}  // namespace clr::scene
