#include "scene/exact_shape.hpp"

#include <algorithm>
#include <cmath>

namespace clr::scene {
namespace {

using Kind = ExactShape::Kind;

// The point of the unit shape at uv (ExactShape::position's parametrisation).
Vec3 local_point(Kind kind, const Vec2& uv) {
  switch (kind) {
    case Kind::sphere: {
      const float theta = kPi * uv.y, phi = 2.0f * kPi * uv.x;
      return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
    }
    case Kind::cylinder: {
      const float phi = 2.0f * kPi * uv.x;
      return {std::cos(phi), std::sin(phi), uv.y};
    }
    case Kind::disk: {
      const float phi = 2.0f * kPi * uv.y;
      return {uv.x * std::cos(phi), uv.x * std::sin(phi), 0.0f};
    }
  }
  return Vec3(0.0f);
}

// φ/2π of a local point's azimuth, in [0, 1).
double azimuth(const glm::dvec3& l) {
  double phi = std::atan2(l.y, l.x);
  if (phi < 0) phi += 2 * M_PI;
  return std::min(phi / (2 * M_PI), std::nextafter(1.0, 0.0));
}

// The uv of a local point on (or near) the unit shape.
Vec2 local_uv(Kind kind, const glm::dvec3& l) {
  switch (kind) {
    case Kind::sphere: {
      const double len = glm::length(l);
      if (!(len > 0)) return Vec2(0.0f);
      const glm::dvec3 d = l / len;
      // θ through asin of a half chord, not acos(z): acos loses all precision near the poles.
      const double theta = d.z >= 0 ? 2 * std::asin(std::min(1.0, 0.5 * glm::length(d - glm::dvec3(0, 0, 1))))
                                    : M_PI - 2 * std::asin(std::min(1.0, 0.5 * glm::length(d + glm::dvec3(0, 0, 1))));
      return {float(azimuth(d)), float(theta / M_PI)};
    }
    case Kind::cylinder:
      return {float(azimuth(l)), float(l.z)};
    case Kind::disk:
      return {float(std::hypot(l.x, l.y)), float(azimuth(l))};
  }
  return Vec2(0.0f);
}

// Whether the columns `a` and `b` are orthogonal and, with `equal`, of one length, to the tolerance of a matrix
// written with six or seven digits (a rotation typed from its cosines, a scale of 1/3).
bool orthogonal(const Vec3& a, const Vec3& b, bool equal) {
  constexpr float kTolerance = 1e-5f;
  const float la = glm::length(a), lb = glm::length(b);
  if (equal && std::fabs(la - lb) > kTolerance * la) return false;
  return std::fabs(glm::dot(a, b)) <= kTolerance * la * lb;
}

}  // namespace

std::optional<ExactShape> ExactShape::from(Kind kind, const glm::mat4& to_world, bool flip) {
  const glm::mat3 m(to_world);
  if (!(std::fabs(glm::determinant(glm::dmat3(m))) > 0)) return std::nullopt;  // in double: tiny scales underflow
  switch (kind) {
    case Kind::sphere:  // a similarity
      if (!orthogonal(m[0], m[1], true) || !orthogonal(m[0], m[2], true) || !orthogonal(m[1], m[2], true))
        return std::nullopt;
      break;
    case Kind::cylinder:  // a round section, square to the axis
      if (!orthogonal(m[0], m[1], true) || !orthogonal(m[0], m[2], false) || !orthogonal(m[1], m[2], false))
        return std::nullopt;
      break;
    case Kind::disk:
      break;  // any linear map takes a disk to an ellipse of constant area density
  }
  ExactShape s;
  s.kind = kind;
  s.origin = Vec3(to_world[3]);
  s.linear = m;
  s.flip = flip;
  s.to_local_ = glm::inverse(glm::dmat3(m));
  s.normal_matrix_ = glm::mat3(glm::transpose(s.to_local_));
  return s;
}

glm::mat4 ExactShape::to_world() const {
  glm::mat4 m(linear);
  m[3] = glm::vec4(origin, 1.0f);
  return m;
}

double ExactShape::area() const {
  const glm::dvec3 x(linear[0]), y(linear[1]), z(linear[2]);
  switch (kind) {
    case Kind::sphere:
      return 4 * M_PI * glm::dot(x, x);
    case Kind::cylinder:
      return 2 * M_PI * glm::length(x) * glm::length(z);
    case Kind::disk:
      return M_PI * glm::length(glm::cross(x, y));
  }
  return 0;
}

Vec3 ExactShape::position(const Vec2& uv) const { return origin + linear * local_point(kind, uv); }

Vec3 ExactShape::normal(const Vec2& uv) const {
  // Normals transform by the inverse transpose, as Mitsuba's to_world.apply(Normal3f) does: the side a mirroring
  // to_world turns a disk's normal to is Mitsuba's.
  Vec3 local = kind == Kind::disk ? Vec3(0, 0, 1) : local_point(kind, uv);
  if (kind == Kind::cylinder) local.z = 0;
  const Vec3 n = glm::normalize(normal_matrix_ * local);
  return flip ? -n : n;
}

Vec2 ExactShape::uv(const glm::dvec3& offset) const { return local_uv(kind, to_local_ * offset); }

void ExactShape::tangents(const Vec2& uv, Vec3& dpdu, Vec3& dpdv) const {
  const float a = 2.0f * kPi * (kind == Kind::disk ? uv.y : uv.x), ca = std::cos(a), sa = std::sin(a);
  switch (kind) {
    case Kind::sphere: {
      const float theta = kPi * uv.y, st = std::sin(theta), ct = std::cos(theta);
      dpdu = linear * Vec3(-st * sa, st * ca, 0.0f) * (2.0f * kPi);
      dpdv = linear * Vec3(ct * ca, ct * sa, -st) * kPi;
      return;
    }
    case Kind::cylinder:
      dpdu = linear * Vec3(-sa, ca, 0.0f) * (2.0f * kPi);
      dpdv = linear[2];
      return;
    case Kind::disk:
      dpdu = linear * Vec3(ca, sa, 0.0f);
      dpdv = linear * Vec3(-sa, ca, 0.0f) * (2.0f * kPi * uv.x);
      return;
  }
}

Vec2 ExactShape::uniform_uv(const Vec2& u) const {
  const Vec2 c = glm::clamp(u, 0.0f, 1.0f);
  switch (kind) {
    // cos θ = 1 − 2ξ is uniform in area; θ = 2·asin(√ξ) is the same angle without acos's loss near the poles.
    case Kind::sphere:
      return {c.x, 2.0f * std::asin(std::sqrt(c.y)) / kPi};
    case Kind::cylinder:
      return c;  // a round section: area is uniform in φ and z
    case Kind::disk:
      return {std::sqrt(c.x), c.y};
  }
  return c;
}

int ExactShape::crossings(const double origin_w[3], const double direction_w[3], double t[2]) const {
  const glm::dvec3 o = to_local_ * (glm::dvec3(origin_w[0], origin_w[1], origin_w[2]) - glm::dvec3(origin));
  const glm::dvec3 d = to_local_ * glm::dvec3(direction_w[0], direction_w[1], direction_w[2]);
  if (kind == Kind::disk) {
    if (!(d.z != 0)) return 0;
    t[0] = -o.z / d.z;
    const double x = o.x + t[0] * d.x, y = o.y + t[0] * d.y;
    return x * x + y * y <= 1 ? 1 : 0;
  }
  // The sphere |o + t·d| = 1, or the tube's section (x and y only).
  const double dz = kind == Kind::sphere ? d.z : 0, oz = kind == Kind::sphere ? o.z : 0;
  const double a = d.x * d.x + d.y * d.y + dz * dz;
  const double b = o.x * d.x + o.y * d.y + oz * dz;
  const double c = o.x * o.x + o.y * o.y + oz * oz - 1;
  const double disc = b * b - a * c;
  if (!(disc >= 0) || !(a > 0)) return 0;
  // The two roots without cancellation: q = −(b + sign(b)·√disc), t = q/a and c/q.
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  double roots[2] = {q / a, q != 0 ? c / q : q / a};
  if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
  int n = 0;
  for (const double r : roots) {
    const double z = o.z + r * d.z;
    if (kind == Kind::sphere || (z >= 0 && z <= 1)) t[n++] = r;
  }
  return n;
}

void ExactShape::bounds(Vec3& lo, Vec3& hi) const {
  // Along world axis i the unit disk spans ±|(row i of its two columns)|; a sphere adds its third column, a
  // cylinder sweeps the disk along it.
  Vec3 e;
  for (int i = 0; i < 3; ++i)
    e[i] = std::sqrt(linear[0][i] * linear[0][i] + linear[1][i] * linear[1][i] +
                     (kind == Kind::sphere ? linear[2][i] * linear[2][i] : 0.0f));
  const Vec3 end = kind == Kind::cylinder ? origin + linear[2] : origin;
  lo = glm::min(origin, end) - e;
  hi = glm::max(origin, end) + e;
}

}  // namespace clr::scene
