#include "scene/camera.hpp"

#include <cmath>

namespace clr::scene {

Vec2 Camera::tan_half_fov() const {
  const float t = std::tan(0.5f * fov_degrees * kPi / 180.0f);
  const float w = float(width), h = float(height);
  FovAxis axis = fov_axis;
  if (axis == FovAxis::smaller) axis = w <= h ? FovAxis::x : FovAxis::y;
  if (axis == FovAxis::larger) axis = w >= h ? FovAxis::x : FovAxis::y;
  switch (axis) {
    case FovAxis::y:
      return {t * w / h, t};
    case FovAxis::diagonal: {
      const float d = std::sqrt(w * w + h * h);
      return {t * w / d, t * h / d};
    }
    default:
      return {t, t * h / w};
  }
}

Camera::Ray Camera::ray(float px, float py) const {
  const Vec2 tan = tan_half_fov();
  const Vec3 local(tan.x * (1.0f - 2.0f * px / float(width)), tan.y * (1.0f - 2.0f * py / float(height)), 1.0f);
  const Vec3 dir_unnormalised = Vec3(to_world * glm::vec4(local, 0.0f));
  const float len = glm::length(dir_unnormalised);
  // The near plane is local z = near_clip, reached at local · near_clip, i.e. at distance near_clip · len.
  return {Vec3(to_world * glm::vec4(0, 0, 0, 1)), dir_unnormalised / len, near_clip * len, far_clip * len};
}

}  // namespace clr::scene
