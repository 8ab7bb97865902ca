#include <algorithm>
#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/bsdfs/bsdf_props.hpp"
#include "scene/fresnel.hpp"
#include "scene/named_ior.hpp"

namespace clr::scene {

namespace {

// Mitsuba 3's roughplastic couples its substrate to the rough coating through two directional averages over the
// microfacets that light arriving at cos θ = mu sees (density G1(wi, m)·(wi·m)·D(m)/cos θi): the transmittance
// (1 − F(wi·m))·G1(wt, m) into the substrate, and the specular albedo F(wi·m)·G1(wr, m) (wt, wr: the refracted
// and reflected directions). Integrated on a stratified grid of D·cos θm samples; for alpha → 0 they tend to the
// smooth 1 − F(mu) and F(mu).
struct InterfaceAverages {
  float transmittance, reflectance;
};

InterfaceAverages rough_interface(const Microfacet& mf, float mu, float eta) {
  constexpr int kGrid = 64;
  const Vec3 wi(std::sqrt(std::fmax(0.0f, 1.0f - mu * mu)), 0.0f, mu);
  double t = 0, r = 0;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const Vec3 m = mf.sample_m(Vec2((float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid));
      const float c = glm::dot(wi, m);
      if (c <= 0) continue;
      const double weight = double(mf.G1(wi, m) * c / (mu * m.z));
      const auto fr = fresnel_dielectric(c, eta);
      r += weight * double(fr.reflectance * mf.G1(reflect(wi, m), m));
      if (fr.reflectance < 1.0f)
        t += weight * double((1.0f - fr.reflectance) * mf.G1(refract(wi, m, c, fr.cos_t, fr.eta_ti), m));
    }
  return {float(t / (kGrid * kGrid)), float(r / (kGrid * kGrid))};
}

constexpr int kTableSize = 64;  // cos θ from 0 to 1; the transmittance is smooth in it

}  // namespace

Plastic::Plastic(float eta, Texture diffuse, Texture specular, bool nonlinear, std::optional<Microfacet> microfacet)
    : eta_(eta),
      diffuse_(std::move(diffuse)),
      specular_(std::move(specular)),
      nonlinear_(nonlinear),
      mf_(microfacet),
      fdr_int_(diffuse_fresnel_reflectance(1.0f / eta)) {
  if (mf_) {
    // A rough coating transmits differently from a smooth one, on the way in and in the internal reflections.
    for (int k = 0; k < kTableSize; ++k)
      rough_transmittance_.push_back(
          rough_interface(*mf_, std::fmax(float(k) / (kTableSize - 1), 1e-3f), eta).transmittance);
    double reflected = 0;  // 2∫ R_inside(μ) μ dμ, midpoint rule
    for (int k = 0; k < kTableSize; ++k) {
      const float mu = (float(k) + 0.5f) / kTableSize;
      reflected += 2.0 * double(rough_interface(*mf_, mu, 1.0f / eta).reflectance * mu) / kTableSize;
    }
    fdr_int_ = float(reflected);
  }
  const float s = luminance(specular_.mean()), d = luminance(diffuse_.mean());
  specular_weight_ = s + d > 0 ? s / (s + d) : 0.5f;
}

float Plastic::transmittance(float cos_theta) const {
  if (!mf_) return 1.0f - fresnel_dielectric(cos_theta, eta_).reflectance;
  const float x = std::clamp(cos_theta, 0.0f, 1.0f) * float(kTableSize - 1);
  const int i = std::min(int(x), kTableSize - 2);
  const float f = x - float(i);
  return (1.0f - f) * rough_transmittance_[std::size_t(i)] + f * rough_transmittance_[std::size_t(i) + 1];
}

float Plastic::specular_probability(float cos_o) const {
  const float t = transmittance(cos_o);
  const float s = (1.0f - t) * specular_weight_, d = t * (1.0f - specular_weight_);
  return s + d > 0 ? s / (s + d) : 0.0f;
}

// The substrate: light refracts in, scatters diffusely (with repeated internal reflections off the coating) and
// refracts out, attenuated by the coating's transmittance both ways.
Rgb Plastic::diffuse_term(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  const Rgb rho = diffuse_.eval(at);
  const Rgb substrate = nonlinear_ ? rho / (Rgb(1.0f) - rho * fdr_int_) : rho / (1.0f - fdr_int_);
  return substrate * (transmittance(wi.z) * transmittance(wo.z) / (eta_ * eta_) * kInvPi * wi.z);
}

Rgb Plastic::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  Rgb result = diffuse_term(at, wo, wi);
  if (mf_) {
    const Vec3 m = glm::normalize(wo + wi);
    const float f = fresnel_dielectric(glm::dot(wo, m), eta_).reflectance;
    result += specular_.eval(at) * (f * mf_->D(m) * mf_->G(wo, wi, m) / (4.0f * wo.z));
  }
  return result;
}

float Plastic::pdf(const TexturePoint&, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0.0f;
  const float ps = specular_probability(wo.z);
  // Smooth: the specular lobe is a delta, so only the diffuse share has a density.
  return mf_ ? glossy_diffuse_pdf(*mf_, ps, wo, wi) : (1.0f - ps) * cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> Plastic::sample(const TexturePoint& at, const Vec3& wo, float u_lobe, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  const float ps = specular_probability(wo.z);
  if (mf_) {
    const auto wi = sample_glossy_diffuse(*mf_, ps, wo, u_lobe, u);
    return wi ? continuous_sample(at, wo, *wi) : std::nullopt;
  }
  if (u_lobe < ps) {
    const float f = fresnel_dielectric(wo.z, eta_).reflectance;
    return BsdfSample{reflect_z(wo), specular_.eval(at) * (f / ps), ps, true};
  }
  const Vec3 wi = sample_cosine_hemisphere(u);
  return wi.z > 0 ? continuous_sample(at, wo, wi) : std::nullopt;
}

}  // namespace clr::scene

namespace clr::scene::loader {
// `plastic` and `roughplastic`.
std::shared_ptr<const Bsdf> read_plastic(Context& ctx, const Props& p) {
  const float eta = read_ior(p, "int_ior", 1.49f) / read_ior(p, "ext_ior", 1.000277f);
  const bool rough = p.type() == "roughplastic";
  if (!rough) ignore_roughness(p);
  const auto mf = rough ? std::optional(read_microfacet(p)) : std::nullopt;
  // The coating's transmittance is tabulated over cos θ alone, which an anisotropic lobe would make depend on φ.
  if (mf && mf->anisotropic())
    p.node.fail("anisotropic roughness is not supported by roughplastic, as in Mitsuba 3 (alpha_u and alpha_v differ)");
  return std::make_shared<Plastic>(eta, ctx.texture(p, "diffuse_reflectance", Rgb(0.5f)),
                                   ctx.texture(p, "specular_reflectance", Rgb(1.0f)), p.boolean("nonlinear", false),
                                   mf);
}
}  // namespace clr::scene::loader
