// Mitsuba 0.6's `roughdiffuse` (Oren and Nayar 1994, "Generalization of Lambert's reflectance model"): the
// qualitative model's single-scattering terms C1–C3 and its interreflection term, or the common A + B
// approximation; cosine-weighted sampling.
#include <algorithm>
#include <cmath>

#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {

Rgb RoughDiffuse::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  const Rgb a = alpha_.eval(at);
  const float sigma = (a.x + a.y + a.z) / 3.0f / std::sqrt(2.0f), s2 = sigma * sigma;
  const float sin_o = std::sqrt(std::fmax(0.0f, 1 - wo.z * wo.z)), sin_i = std::sqrt(std::fmax(0.0f, 1 - wi.z * wi.z));
  // cos(φi − φo), 0 where either direction is the normal (φ undefined).
  const float cos_phi = sin_o > 1e-6f && sin_i > 1e-6f ? (wo.x * wi.x + wo.y * wi.y) / (sin_o * sin_i) : 0.0f;
  // α the larger polar angle, β the smaller.
  const bool o_steeper = wo.z > wi.z;  // wo closer to the normal: β = θo
  const float sin_alpha = o_steeper ? sin_i : sin_o, sin_beta = o_steeper ? sin_o : sin_i;
  const float tan_beta = o_steeper ? sin_o / wo.z : sin_i / wi.z;
  const Rgb rho = reflectance_.eval(at);
  if (fast_) {
    const float A = 1 - 0.5f * s2 / (s2 + 0.33f), B = 0.45f * s2 / (s2 + 0.09f);
    return rho * (kInvPi * wi.z * (A + B * std::fmax(cos_phi, 0.0f) * sin_alpha * tan_beta));
  }
  const float theta_alpha = std::acos(std::min(wo.z, wi.z)), theta_beta = std::acos(std::max(wo.z, wi.z));
  const float k = s2 / (s2 + 0.09f), ab = 4 * kInvPi * kInvPi * theta_alpha * theta_beta;
  const float beta_term = 2 * theta_beta * kInvPi;
  const float c1 = 1 - 0.5f * s2 / (s2 + 0.33f);
  const float c2 = 0.45f * k * (cos_phi > 0 ? sin_alpha : sin_alpha - beta_term * beta_term * beta_term);
  const float c3 = 0.125f * k * ab * ab;
  const float c4 = 0.17f * s2 / (s2 + 0.13f);
  const float cos_alpha = std::sqrt(std::fmax(0.0f, 1 - sin_alpha * sin_alpha)),
              cos_beta = std::sqrt(std::fmax(0.0f, 1 - sin_beta * sin_beta));
  const float tan_half = (sin_alpha + sin_beta) / (cos_alpha + cos_beta);  // tan((α + β) / 2)
  const Rgb single = rho * (c1 + cos_phi * c2 * tan_beta + (1 - std::fabs(cos_phi)) * c3 * tan_half);
  const Rgb twice = rho * rho * (c4 * (1 - cos_phi * beta_term * beta_term));
  return (single + twice) * (kInvPi * wi.z);
}

float RoughDiffuse::pdf(const TexturePoint&, const Vec3& wo, const Vec3& wi) const {
  return wo.z <= 0 || wi.z <= 0 ? 0.0f : cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> RoughDiffuse::sample(const TexturePoint& at, const Vec3& wo, float, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  const Vec3 wi = sample_cosine_hemisphere(u);
  const float p = cosine_hemisphere_pdf(wi.z);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{wi, eval(at, wo, wi) / p, p, false};
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_roughdiffuse(Context& ctx, const Props& p) {
  if (p.has("reflectance") && p.has("diffuse_reflectance"))
    p.node.fail("give either 'reflectance' or 'diffuse_reflectance', not both");
  const std::string name = p.has("diffuse_reflectance") ? "diffuse_reflectance" : "reflectance";
  const Texture alpha = ctx.texture(p, "alpha", Rgb(0.2f));
  if (!(alpha.mean().x >= 0)) p.node.fail("alpha must be non-negative");
  return std::make_shared<RoughDiffuse>(ctx.texture(p, name, Rgb(0.5f)), alpha, p.boolean("use_fast_approx", false));
}
}  // namespace clr::scene::loader
