#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/fresnel.hpp"
#include "scene/named_ior.hpp"

namespace clr::scene {

Microfacet RoughnessTextures::at(const Microfacet& base, const TexturePoint& point) const {
  Microfacet m = base;
  m.alpha = std::fmax(alpha_u.eval_1(point), 1e-4f);
  m.alpha_v = std::fmax(alpha_v.eval_1(point), 1e-4f);
  return m;
}

Microfacet Conductor::microfacet(const TexturePoint& at) const { return textured_ ? textured_->at(*mf_, at) : *mf_; }

Rgb Conductor::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (!mf_ || wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  const Microfacet mf = microfacet(at);
  const Vec3 m = glm::normalize(wo + wi);
  const float d = mf.D(m);
  if (d == 0.0f) return Rgb(0.0f);
  const Rgb f = fresnel_conductor(glm::dot(wo, m), eta_, k_);
  return specular_.eval(at) * f * (d * mf.G(wo, wi, m) / (4.0f * wo.z));
}

float Conductor::pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (!mf_ || wo.z <= 0 || wi.z <= 0) return 0.0f;
  const Vec3 m = glm::normalize(wo + wi);
  return microfacet(at).pdf_m(m) / (4.0f * glm::dot(wo, m));
}

std::optional<BsdfSample> Conductor::sample(const TexturePoint& at, const Vec3& wo, float, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  if (!mf_) return BsdfSample{reflect_z(wo), specular_.eval(at) * fresnel_conductor(wo.z, eta_, k_), 1.0f, true};
  const Vec3 wi = reflect(wo, microfacet(at).sample_m(u));
  if (wi.z <= 0) return std::nullopt;
  return continuous_sample(at, wo, wi);
}

Rgb Conductor::albedo(const TexturePoint& at) const { return specular_.eval(at) * fresnel_conductor(1.0f, eta_, k_); }

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
  std::optional<RoughnessTextures> textured;
  std::optional<Microfacet> mf;
  if (rough) mf = read_rough_microfacet(ctx, p, textured);
  return std::make_shared<Conductor>(c.eta / ext, c.k / ext, ctx.texture(p, "specular_reflectance", Rgb(1.0f)), mf,
                                     textured);
}
}  // namespace clr::scene::loader
