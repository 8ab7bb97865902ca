#pragma once
// Isotropic microfacet distributions (Walter et al. 2007) with the separable Smith shadowing term. Normals are
// sampled from D(m)·cos θm, so pdf_m(m) = D(m)·cos θm for both distributions.
#include <cmath>

#include "scene/frame.hpp"

namespace clr::scene {

struct Microfacet {
  enum class Type { beckmann, ggx };
  Type type = Type::beckmann;
  float alpha = 0.1f;

  float D(const Vec3& m) const {
    if (m.z <= 0) return 0.0f;
    const float c2 = m.z * m.z, a2 = alpha * alpha;
    if (type == Type::beckmann) {
      const float tan2 = (1.0f - c2) / c2;
      return std::exp(-tan2 / a2) / (kPi * a2 * c2 * c2);
    }
    const float d = c2 * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
  }

  // Smith's Λ for the direction w (its tan θ), exact for both distributions.
  float lambda(const Vec3& w) const {
    const float c2 = w.z * w.z;
    const float tan2 = std::fmax(0.0f, 1.0f - c2) / c2;
    if (tan2 == 0.0f) return 0.0f;
    if (type == Type::ggx) return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
    const float a = 1.0f / (alpha * std::sqrt(tan2));
    return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
  }
  // Zero when w sees the back of the microfacet (w·m and w·n of different signs).
  float G1(const Vec3& w, const Vec3& m) const {
    if (glm::dot(w, m) * w.z <= 0) return 0.0f;
    return 1.0f / (1.0f + lambda(w));
  }
  float G(const Vec3& wo, const Vec3& wi, const Vec3& m) const { return G1(wo, m) * G1(wi, m); }

  Vec3 sample_m(const Vec2& u) const {
    const float tan2 = type == Type::beckmann ? -alpha * alpha * std::log1p(-u.x)
                                              : alpha * alpha * u.x / std::fmax(1.0f - u.x, 1e-12f);
    const float cos_t = 1.0f / std::sqrt(1.0f + tan2), sin_t = std::sqrt(std::fmax(0.0f, 1.0f - cos_t * cos_t));
    const float phi = 2.0f * kPi * u.y;
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
  }
  float pdf_m(const Vec3& m) const { return D(m) * m.z; }
};

}  // namespace clr::scene
