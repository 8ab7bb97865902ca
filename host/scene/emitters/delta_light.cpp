#include "scene/delta_light.hpp"

#include <cmath>

namespace clr::scene {

DeltaLight::Arrival DeltaLight::arrive(const Vec3& p) const {
  if (kind == Kind::directional) return {-direction, std::numeric_limits<float>::infinity(), intensity};
  const Vec3 d = position - p;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0)) return {Vec3(0, 0, 1), 0.0f, Rgb(0.0f)};
  const float dist = std::sqrt(dist2);
  Arrival a{d / dist, dist, intensity / dist2};
  if (kind == Kind::point) return a;
  const Vec3 local = Vec3(to_local * glm::vec4(p, 1.0f));  // the lit point in the light's frame
  if (!(local.z > 0)) return {a.direction, dist, Rgb(0.0f)};
  if (kind == Kind::spot) {
    // Mitsuba: full intensity within the beam width, falling linearly in angle to zero at the cutoff.
    const float cos_theta = local.z / glm::length(local), theta = std::acos(std::fmin(cos_theta, 1.0f));
    if (theta >= cutoff) return {a.direction, dist, Rgb(0.0f)};
    if (theta > beam_width) a.radiance *= (cutoff - theta) / (cutoff - beam_width);
    if (texture) {
      const float uv_factor = std::tan(cutoff);
      a.radiance *= texture->eval(
          Vec2(0.5f + 0.5f * local.x / (local.z * uv_factor), 0.5f + 0.5f * local.y / (local.z * uv_factor)));
    }
    return a;
  }
  // Projector: the image lies on the plane z = 1 of a perspective camera's frame, the irradiance it gives there is
  // the texture's (times `scale`); a plane at depth z receives it spread as 1/z² and tilted by 1/cos.
  const Vec2 tan = projection.tan_half_fov();
  const Vec2 uv(0.5f - 0.5f * local.x / (local.z * tan.x), 0.5f - 0.5f * local.y / (local.z * tan.y));
  if (uv.x < 0 || uv.x > 1 || uv.y < 0 || uv.y > 1) return {a.direction, dist, Rgb(0.0f)};
  const float cos_axis = local.z / glm::length(local);
  a.radiance = intensity * texture->eval(uv) * (kPi / (local.z * local.z * cos_axis));
  return a;
}

}  // namespace clr::scene
