// Mitsuba's `pplastic` (polarized plastic), in its unpolarized form: the two lobes of Baek et al. 2018 with scalar
// Fresnel factors in place of Mueller matrices, which is what Mitsuba's RGB variants evaluate.
#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/fresnel.hpp"

namespace clr::scene {

namespace {
float channel_mean(const Rgb& c) { return (c.x + c.y + c.z) / 3.0f; }
}  // namespace

PolarizedPlastic::PolarizedPlastic(float eta, Texture diffuse, std::optional<Texture> specular, Microfacet microfacet)
    : eta_(eta), diffuse_(std::move(diffuse)), specular_(std::move(specular)), mf_(microfacet) {
  const float d = channel_mean(diffuse_.mean()), s = specular_ ? channel_mean(specular_->mean()) : 1.0f;
  specular_probability_ = d + s > 0 ? s / (d + s) : 0.5f;
}

Rgb PolarizedPlastic::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  const Vec3 m = glm::normalize(wo + wi);
  const float f = fresnel_dielectric(glm::dot(wo, m), eta_).reflectance;
  Rgb specular(f * mf_.D(m) * mf_.G(wo, wi, m) / (4.0f * wo.z));
  if (specular_) specular *= specular_->eval(at);
  const float t_o = 1.0f - fresnel_dielectric(wo.z, eta_).reflectance,
              t_i = 1.0f - fresnel_dielectric(wi.z, eta_).reflectance;
  return specular + diffuse_.eval(at) * (t_o * t_i * kInvPi * wi.z);
}

float PolarizedPlastic::pdf(const TexturePoint&, const Vec3& wo, const Vec3& wi) const {
  return glossy_diffuse_pdf(mf_, specular_probability_, wo, wi);
}

std::optional<BsdfSample> PolarizedPlastic::sample(const TexturePoint& at, const Vec3& wo, float u_lobe,
                                                   const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  const auto wi = sample_glossy_diffuse(mf_, specular_probability_, wo, u_lobe, u);
  return wi ? continuous_sample(at, wo, *wi) : std::nullopt;
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_pplastic(Context& ctx, const Props& p) {
  const float int_ior = read_ior(p, "int_ior", 1.49f), ext_ior = read_ior(p, "ext_ior", 1.000277f);
  if (int_ior == ext_ior) p.node.fail("the interior and exterior IORs must differ");
  std::optional<Texture> specular;
  if (p.has("specular_reflectance")) specular = ctx.texture(p, "specular_reflectance", Rgb(1.0f));
  return std::make_shared<PolarizedPlastic>(int_ior / ext_ior, ctx.texture(p, "diffuse_reflectance", Rgb(0.5f)),
                                            specular, read_microfacet(p));
}
}  // namespace clr::scene::loader
