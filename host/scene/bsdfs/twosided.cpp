#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {
namespace {
Vec3 flip(const Vec3& w) { return {w.x, w.y, -w.z}; }
}  // namespace

Rgb TwoSided::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  return wo.z >= 0 ? nested_->eval(at, wo, wi) : back_->eval(at, flip(wo), flip(wi));
}

float TwoSided::pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  return wo.z >= 0 ? nested_->pdf(at, wo, wi) : back_->pdf(at, flip(wo), flip(wi));
}

std::optional<BsdfSample> TwoSided::sample(const TexturePoint& at, const Vec3& wo, float u_lobe, const Vec2& u) const {
  if (wo.z >= 0) return nested_->sample(at, wo, u_lobe, u);
  auto s = back_->sample(at, flip(wo), u_lobe, u);
  if (s) s->wi = flip(s->wi);
  return s;
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_twosided(Context& ctx, const Props& p) {
  auto nested = ctx.nested_bsdfs(p);
  if (nested.empty() || nested.size() > 2) p.node.fail("twosided expects one or two nested BSDFs");
  return std::make_shared<TwoSided>(nested.front(), nested.back());
}
}  // namespace clr::scene::loader
