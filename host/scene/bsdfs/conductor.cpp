#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/fresnel.hpp"
#include "scene/named_ior.hpp"

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

namespace clr::scene::loader {
// `conductor` and `roughconductor`.
std::shared_ptr<const Bsdf> read_conductor(Context& ctx, const Props& p) {
  ComplexIor c{Rgb(0.0f), Rgb(1.0f)};
  if (p.has("eta") || p.has("k")) {
    c = {p.color("eta", Rgb(0.0f)), p.color("k", Rgb(1.0f))};
  } else {
    const std::string m = p.string("material", "none");
    const auto named = conductor_ior(m);
    if (!named) p.expect("material", {"string"}).fail("unknown conductor material '" + m + "'");
    c = *named;
  }
  const float ext = read_ior(p, "ext_eta", 1.0f);
  const bool rough = p.type() == "roughconductor";
  if (!rough) ignore_roughness(p);
  return std::make_shared<Conductor>(c.eta / ext, c.k / ext, ctx.texture(p, "specular_reflectance", Rgb(1.0f)),
                                     rough ? std::optional(read_microfacet(p)) : std::nullopt);
}
}  // namespace clr::scene::loader
