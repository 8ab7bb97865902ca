#include "scene/camera.hpp"

#include <cmath>

#include "common/error.hpp"

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

Camera::PixelSample Camera::pixel_sample(std::size_t x, std::size_t y, Pcg32& rng) const {
  // Positions stay on the film, as Mitsuba's: a pixel at its edge averages what its filter covers there.
  const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
  const PixelFilter::Sample sx = filter.sample(rng, -cx, float(width) - cx);
  const PixelFilter::Sample sy = filter.sample(rng, -cy, float(height) - cy);
  return {cx + sx.offset, cy + sy.offset, sx.weight * sy.weight};
}

namespace {
// Shirley and Chiu's concentric map of the unit square onto the unit disk (Mitsuba's choice for apertures).
Vec2 square_to_disk(const Vec2& u) {
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0 && b == 0) return Vec2(0.0f);
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = 0.25f * kPi * (b / a);
  } else {
    r = b;
    phi = 0.5f * kPi - 0.25f * kPi * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}
}  // namespace

Camera Camera::pinhole_view(std::span<const float> c, const std::string& what) const {
  if (c.size() != 10)
    throw InputError(what + ": give 10 numbers (origin, target, up, vertical fov in degrees), not " +
                     std::to_string(c.size()));
  for (const float v : c)
    if (!std::isfinite(v)) throw InputError(what + ": every number must be finite");
  const auto frame = look_at({c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]});
  if (!frame || !(c[9] > 0 && c[9] < 180))
    throw InputError(what +
                     ": origin and target must differ, up must not be parallel to the view, and fov must be in (0, "
                     "180)");
  Camera view = *this;
  view.to_world = *frame;
  view.fov_degrees = c[9];
  view.fov_axis = FovAxis::y;
  view.projection = Projection::perspective;
  view.aperture_radius = 0;
  view.principal_point_offset = Vec2(0.0f);  // a view through its centre
  view.validate(what);
  return view;
}

Camera Camera::resized(int new_width, int new_height) const {
  Camera c = *this;
  if (new_width > 0) c.width = new_width;
  if (new_height > 0) c.height = new_height;
  return c;
}

namespace {
bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

std::optional<glm::mat4> look_at(const Vec3& origin, const Vec3& target, const Vec3& up) {
  const Vec3 dir = target - origin, left = glm::cross(up, dir);
  if (!(glm::length(dir) > 0) || !(glm::length(left) > 0)) return std::nullopt;
  const Vec3 d = glm::normalize(dir), l = glm::normalize(left), u = glm::cross(d, l);
  if (!finite(d) || !finite(l)) return std::nullopt;  // lengths that underflow when squared
  return glm::mat4(glm::vec4(l, 0), glm::vec4(u, 0), glm::vec4(d, 0), glm::vec4(origin, 1));
}

void Camera::validate(const std::string& what) const {
  const Vec3 origin(to_world * glm::vec4(0, 0, 0, 1)), view(to_world * glm::vec4(0, 0, 1, 0));
  if (!finite(origin) || glm::any(glm::greaterThan(glm::abs(origin), Vec3(kMaxCoordinate))))
    throw InputError(what +
                     ": the camera's position lies beyond ±1e12 (or is not finite), farther than "
                     "single-precision ray tracing can resolve");
  if (!finite(view) || !(glm::length(view) > 0))
    throw InputError(what + ": the camera's view direction is not finite or zero");
  if (projection == Projection::perspective && !(fov_degrees > 0 && fov_degrees < 180))
    throw InputError(what + ": the field of view must be in (0, 180)");
}

Camera::Ray Camera::ray(float px, float py, const Vec2& lens) const {
  const Vec2 screen(1.0f - 2.0f * (px / float(width) + principal_point_offset.x),
                    1.0f - 2.0f * (py / float(height) + principal_point_offset.y));
  if (projection == Projection::orthographic) {
    const Vec3 axis = Vec3(to_world * glm::vec4(0, 0, 1, 0));
    const float len = glm::length(axis);
    const Vec3 origin(to_world * glm::vec4(screen.x, screen.y * float(height) / float(width), 0, 1));
    // The clip planes lie at local depths near_clip and far_clip, reached after near_clip · len along the ray.
    return {origin, axis / len, near_clip * len, far_clip * len};
  }
  const Vec2 tan = tan_half_fov();
  Vec3 local(tan.x * screen.x, tan.y * screen.y, 1.0f);
  Vec3 origin_local(0.0f);
  if (aperture_radius > 0) {
    // A thin lens: rays from a point of the aperture through the point of the focal plane the pinhole ray meets.
    const Vec2 a = aperture_radius * square_to_disk(lens);
    origin_local = Vec3(a, 0.0f);
    local = local * focus_distance - origin_local;
    local /= local.z;
  }
  const Vec3 dir_unnormalised = Vec3(to_world * glm::vec4(local, 0.0f));
  const float len = glm::length(dir_unnormalised);
  // The near plane is local z = near_clip, reached at local · near_clip, i.e. at distance near_clip · len.
  return {Vec3(to_world * glm::vec4(origin_local, 1.0f)), dir_unnormalised / len, near_clip * len, far_clip * len};
}

}  // namespace clr::scene
