#pragma once
// Microfacet distributions (Walter et al. 2007), isotropic or anisotropic (roughness alpha along the shading
// frame's x, alpha_v along its y), with the separable Smith shadowing term. Normals are sampled from D(m)·cos θm
// by stretching the slopes of the unit-roughness distribution (Heitz 2014), so pdf_m(m) = D(m)·cos θm for both.
#include <cmath>
#include <optional>

#include "scene/frame.hpp"

namespace clr::scene {

struct Microfacet {
  enum class Type { beckmann, ggx };
  Type type = Type::beckmann;
  float alpha = 0.1f;    // along x (Mitsuba's alpha_u, or alpha)
  float alpha_v = 0.0f;  // along y; 0: the same as alpha (isotropic)

  float av() const { return alpha_v > 0 ? alpha_v : alpha; }
  // One roughness for what needs a single number (the network's input): the geometric mean.
  float mean_alpha() const { return std::sqrt(alpha * av()); }
  bool anisotropic() const { return alpha_v > 0 && alpha_v != alpha; }

  float D(const Vec3& m) const {
    if (m.z <= 0) return 0.0f;
    const float ax = alpha, ay = av(), c2 = m.z * m.z;
    // tan² θm stretched by the roughness along each axis.
    const float t2 = (m.x * m.x / (ax * ax) + m.y * m.y / (ay * ay)) / c2;
    if (type == Type::beckmann) return std::exp(-t2) / (kPi * ax * ay * c2 * c2);
    const float d = c2 * (1.0f + t2);
    return 1.0f / (kPi * ax * ay * d * d);
  }

  // Smith's Λ for the direction w: the roughness along w's azimuth times its tan θ.
  float lambda(const Vec3& w) const {
    const float c2 = w.z * w.z;
    const float ax = alpha, ay = av();
    const float a2t2 = (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / c2;  // α(φ)² tan² θ
    if (!(a2t2 > 0)) return 0.0f;
    if (type == Type::ggx) return 0.5f * (std::sqrt(1.0f + a2t2) - 1.0f);
    const float a = 1.0f / std::sqrt(a2t2);
    return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
  }
  // Zero when w sees the back of the microfacet (w·m and w·n of different signs).
  float G1(const Vec3& w, const Vec3& m) const {
    if (glm::dot(w, m) * w.z <= 0) return 0.0f;
    return 1.0f / (1.0f + lambda(w));
  }
  float G(const Vec3& wo, const Vec3& wi, const Vec3& m) const { return G1(wo, m) * G1(wi, m); }

  Vec3 sample_m(const Vec2& u) const {
    // tan θ of the unit-roughness distribution, then its slope stretched by (alpha, alpha_v).
    const float tan2 = type == Type::beckmann ? -std::log1p(-u.x) : u.x / std::fmax(1.0f - u.x, 1e-12f);
    const float t = std::sqrt(tan2), phi = 2.0f * kPi * u.y;
    return glm::normalize(Vec3(alpha * t * std::cos(phi), av() * t * std::sin(phi), 1.0f));
  }
  float pdf_m(const Vec3& m) const { return D(m) * m.z; }
};

// The microfacet normal of a reflection or refraction pair (wo, wi), oriented to +z; the zero vector when there is
// none. `eta`: IOR below the surface over above.
inline Vec3 half_vector(const Vec3& wo, const Vec3& wi, float eta) {
  const bool reflection = wo.z * wi.z > 0;
  const float eta_rel = wo.z > 0 ? eta : 1.0f / eta;  // IOR on wi's side over wo's, for refraction
  Vec3 m = reflection ? wo + wi : wo + wi * eta_rel;
  const float len = glm::length(m);
  if (!(len > 0)) return Vec3(0.0f);
  m /= len;
  return m.z < 0 ? -m : m;
}

// A glossy lobe beside a diffuse one (plastic, pplastic, ward): with probability ps a microfacet normal from `mf`
// reflects wo, else a cosine-weighted direction. The mixture's density, and a direction drawn from it (nullopt
// below the surface); both for wo above it.
inline float glossy_diffuse_pdf(const Microfacet& mf, float ps, const Vec3& wo, const Vec3& wi) {
  if (wo.z <= 0 || wi.z <= 0) return 0.0f;
  const Vec3 m = glm::normalize(wo + wi);
  return ps * mf.pdf_m(m) / (4.0f * glm::dot(wo, m)) + (1.0f - ps) * cosine_hemisphere_pdf(wi.z);
}
inline std::optional<Vec3> sample_glossy_diffuse(const Microfacet& mf, float ps, const Vec3& wo, float u_lobe,
                                                 const Vec2& u) {
  const Vec3 wi = u_lobe < ps ? reflect(wo, mf.sample_m(u)) : sample_cosine_hemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  return wi;
}

}  // namespace clr::scene
