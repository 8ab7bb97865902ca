// Mitsuba's `blendbsdf`: a linear blend of two BSDFs, sampled by choosing one with the blend's probability.
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {

Rgb BlendBsdf::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  const float w = weight(at);
  return (1.0f - w) * a_->eval(at, wo, wi) + w * b_->eval(at, wo, wi);
}

float BlendBsdf::pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  const float w = weight(at);
  return (1.0f - w) * a_->pdf(at, wo, wi) + w * b_->pdf(at, wo, wi);
}

std::optional<BsdfSample> BlendBsdf::sample(const TexturePoint& at, const Vec3& wo, float u_lobe, const Vec2& u) const {
  const float w = weight(at);
  const bool second = u_lobe < w;
  // The lobe variable, reused for the chosen BSDF's own choice.
  const float u_rest = second ? u_lobe / w : (u_lobe - w) / (1.0f - w);
  auto s = (second ? b_ : a_)->sample(at, wo, std::fmin(u_rest, 0x1.fffffep-1f), u);
  if (!s) return std::nullopt;
  if (s->delta) {
    // A delta lobe of one BSDF: chosen with the blend's probability times its own, valued at the blend's factor.
    s->pdf *= second ? w : 1.0f - w;
    return s;
  }
  const float p = pdf(at, wo, s->wi);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{s->wi, eval(at, wo, s->wi) / p, p, false};
}

Rgb BlendBsdf::albedo(const TexturePoint& at) const {
  const float w = weight(at);
  return (1.0f - w) * a_->albedo(at) + w * b_->albedo(at);
}

float BlendBsdf::roughness() const {
  const float w = std::clamp(weight_.mean_1(), 0.0f, 1.0f);
  return (1.0f - w) * a_->roughness() + w * b_->roughness();
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_blendbsdf(Context& ctx, const Props& p) {
  const Texture weight = ctx.scalar_texture(p, "weight", Rgb(0.5f));
  const float mean = weight.mean_1();
  if (!(mean >= 0 && mean <= 1)) p.node.fail("weight must lie in [0, 1]");
  auto nested = ctx.nested_bsdfs(p);
  if (nested.size() != 2) p.node.fail("blendbsdf expects exactly two nested BSDFs");
  return std::make_shared<BlendBsdf>(weight, nested[0], nested[1]);
}
}  // namespace clr::scene::loader
