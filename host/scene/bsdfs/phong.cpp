// Mitsuba 0.6's `phong`: the energy-normalised modified Phong model, a Lambertian lobe plus
// specular·(n + 2)/2π·cos^n α around the mirror direction (α its angle to wi), each sampled in proportion to its
// mean reflectance's luminance.
#include <cmath>
#include <cstdio>

#include "common/terminal_text.hpp"
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {

namespace {
Vec3 mirror(const Vec3& w) { return {-w.x, -w.y, w.z}; }
}  // namespace

Phong::Phong(Texture diffuse, Texture specular, float exponent)
    : diffuse_(std::move(diffuse)), specular_(std::move(specular)), exponent_(exponent) {
  const float d = luminance(diffuse_.mean()), s = luminance(specular_.mean());
  specular_probability_ = d + s > 0 ? s / (d + s) : 0.5f;
}

Rgb Phong::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  const float cos_alpha = glm::dot(mirror(wo), wi);
  Rgb f = diffuse_.eval(at) * kInvPi;
  if (cos_alpha > 0) f += specular_.eval(at) * ((exponent_ + 2) * 0.5f * kInvPi * std::pow(cos_alpha, exponent_));
  return f * wi.z;
}

float Phong::pdf(const TexturePoint&, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0.0f;
  const float cos_alpha = glm::dot(mirror(wo), wi);
  const float p_spec = cos_alpha > 0 ? (exponent_ + 1) * 0.5f * kInvPi * std::pow(cos_alpha, exponent_) : 0.0f;
  return specular_probability_ * p_spec + (1 - specular_probability_) * cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> Phong::sample(const TexturePoint& at, const Vec3& wo, float u_lobe, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  Vec3 wi;
  if (u_lobe < specular_probability_) {
    // cos α = u^(1/(n+1)): the lobe's density (n + 1)/2π·cos^n α around the mirror direction.
    const float cos_a = std::pow(u.x, 1.0f / (exponent_ + 1)), sin_a = std::sqrt(std::fmax(0.0f, 1 - cos_a * cos_a));
    const float phi = 2 * kPi * u.y;
    wi = Frame(mirror(wo)).to_world(Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a));
  } else {
    wi = sample_cosine_hemisphere(u);
  }
  if (wi.z <= 0) return std::nullopt;
  return continuous_sample(at, wo, wi);
}

}  // namespace clr::scene

namespace clr::scene::loader {
namespace {
// Mitsuba 0.6's ensureEnergyConservation: a constant reflectance above 1 is scaled down to 1, with a warning.
Texture at_most_one(const Props& p, const std::string& name, const Texture& t) {
  if (!t.is_constant() || !p.boolean("ensure_energy_conservation", true)) return t;
  const float m = max_component(t.mean());
  if (m <= 1) return t;
  std::fprintf(stderr, "%s: warning: '%s' above 1 scaled down to conserve energy (as Mitsuba 0.6)\n",
               clr::terminal_safe(p.node.where()).c_str(), name.c_str());
  return Texture(t.mean() / m);
}
}  // namespace

std::shared_ptr<const Bsdf> read_phong(Context& ctx, const Props& p) {
  const float exponent = p.number("exponent", 30.0f);
  if (!(exponent >= 0)) p.expect("exponent", {"float"}).fail("exponent must be non-negative");
  const Texture d = at_most_one(p, "diffuse_reflectance", ctx.texture(p, "diffuse_reflectance", Rgb(0.5f)));
  const Texture s = at_most_one(p, "specular_reflectance", ctx.texture(p, "specular_reflectance", Rgb(0.2f)));
  return std::make_shared<Phong>(d, s, exponent);
}
}  // namespace clr::scene::loader
