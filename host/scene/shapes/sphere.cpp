#include "scene/sphere.hpp"

#include <algorithm>
#include <cmath>

namespace clr::scene {

std::optional<Sphere> Sphere::from(const glm::mat4& to_world, bool flip) {
  const glm::mat3 m(to_world);
  const float scale = glm::length(m[0]);
  if (!(scale > 0)) return std::nullopt;
  // Mitsuba refuses a sphere whose to_world is not a similarity; the tolerance is that of a matrix written with
  // six or seven digits (a rotation typed from its cosines, a scale of 1/3).
  constexpr float kTolerance = 1e-5f;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(glm::length(m[i]) - scale) > kTolerance * scale) return std::nullopt;
    for (int j = i + 1; j < 3; ++j)
      if (std::fabs(glm::dot(m[i], m[j])) > kTolerance * scale * scale) return std::nullopt;
  }
  Sphere s;
  s.center = Vec3(to_world[3]);
  s.radius = scale;
  s.axes = m / scale;
  s.flip = flip;
  return s;
}

glm::mat4 Sphere::to_world() const {
  glm::mat4 m(axes * radius);
  m[3] = glm::vec4(center, 1.0f);
  return m;
}

double Sphere::area() const { return 4.0 * M_PI * double(radius) * double(radius); }

Vec3 Sphere::direction(const Vec2& uv) const {
  const float theta = kPi * uv.y, phi = 2.0f * kPi * uv.x;
  return axes * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

Vec2 Sphere::uv(const Vec3& direction) const {
  const Vec3 d = glm::transpose(axes) * direction;
  const float len = glm::length(d);
  if (!(len > 0)) return Vec2(0.0f);
  const Vec3 l = d / len;
  // θ through asin of a half chord, not acos(z): acos loses all precision near the poles.
  const float theta = l.z >= 0 ? 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(Vec3(l.x, l.y, l.z - 1.0f))))
                               : kPi - 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(Vec3(l.x, l.y, l.z + 1.0f))));
  float phi = std::atan2(l.y, l.x);
  if (phi < 0) phi += 2.0f * kPi;
  return {phi / (2.0f * kPi), theta / kPi};
}

void Sphere::tangents(const Vec2& uv, Vec3& dpdu, Vec3& dpdv) const {
  const float theta = kPi * uv.y, phi = 2.0f * kPi * uv.x;
  const float st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
  dpdu = axes * Vec3(-st * sp, st * cp, 0.0f) * (2.0f * kPi * radius);
  dpdv = axes * Vec3(ct * cp, ct * sp, -st) * (kPi * radius);
}

Vec2 Sphere::uniform_uv(const Vec2& u) {
  // cos θ = 1 − 2ξ is uniform in area; θ = 2·asin(√ξ) is the same angle without acos's loss near the poles.
  return {u.x, 2.0f * std::asin(std::sqrt(std::clamp(u.y, 0.0f, 1.0f))) / kPi};
}

}  // namespace clr::scene
