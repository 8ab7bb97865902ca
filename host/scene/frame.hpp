#pragma once
// Vector types of the scene room and the orthonormal shading frame BSDFs work in (z = shading normal).
#include <cmath>
#include <glm/glm.hpp>

namespace clr::scene {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Rgb = glm::vec3;  // linear RGB

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
// The largest |coordinate| of a vertex or camera: single-precision ray tracing resolves nothing finer than ~1e5 out
// there already, and Embree refuses rays whose origin lies beyond ~1.8e19 (an assertion, not an error), so
// anything farther is refused when the scene is read, naming it.
inline constexpr float kMaxCoordinate = 1e12f;

inline float luminance(const Rgb& c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }
inline float max_component(const Rgb& c) { return std::fmax(c.x, std::fmax(c.y, c.z)); }
inline bool is_black(const Rgb& c) { return c.x == 0.0f && c.y == 0.0f && c.z == 0.0f; }

struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  Frame() = default;
  // Any orthonormal tangents around a unit normal (Duff et al. 2017: branch-free, no singularity at n = -z).
  explicit Frame(const Vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
  }
  Vec3 to_local(const Vec3& v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

inline Vec3 reflect_z(const Vec3& w) { return {-w.x, -w.y, w.z}; }
inline Vec3 reflect(const Vec3& w, const Vec3& m) { return 2.0f * glm::dot(w, m) * m - w; }

// Sampling on the sphere from two uniforms; each comes with its pdf (solid angle).
inline Vec3 sample_cosine_hemisphere(const Vec2& u) {
  const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1.0f - u.x))};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0 ? cos_theta * kInvPi : 0.0f; }
inline Vec3 sample_uniform_sphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 0.25f * kInvPi;

}  // namespace clr::scene
