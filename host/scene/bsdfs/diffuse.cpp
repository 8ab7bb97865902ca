#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene {

// One-sided like Mitsuba's: light arriving at or leaving the back is absorbed (`twosided` makes both sides scatter).
Rgb Diffuse::eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
  return reflectance_.eval(at) * (kInvPi * wi.z);
}

float Diffuse::pdf(const TexturePoint&, const Vec3& wo, const Vec3& wi) const {
  return wo.z <= 0 ? 0.0f : cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> Diffuse::sample(const TexturePoint& at, const Vec3& wo, float, const Vec2& u) const {
  if (wo.z <= 0) return std::nullopt;
  const Vec3 wi = sample_cosine_hemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  return BsdfSample{wi, reflectance_.eval(at), cosine_hemisphere_pdf(wi.z), false};
}

}  // namespace clr::scene

namespace clr::scene::loader {
std::shared_ptr<const Bsdf> read_diffuse(Context& ctx, const Props& p) {
  return std::make_shared<Diffuse>(ctx.texture(p, "reflectance", Rgb(0.5f)));
}
}  // namespace clr::scene::loader
