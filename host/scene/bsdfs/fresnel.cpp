#include "scene/fresnel.hpp"

#include <cmath>

namespace clr::scene {

FresnelDielectric fresnel_dielectric(float cos_i, float eta) {
  const bool outside = cos_i >= 0;
  const float eta_ti = outside ? eta : 1.0f / eta;
  const float ci = std::fabs(cos_i);
  const float sin2_t = (1.0f - ci * ci) / (eta_ti * eta_ti);
  if (sin2_t >= 1.0f) return {1.0f, 0.0f, eta_ti};
  const float ct = std::sqrt(1.0f - sin2_t);
  const float rs = (ci - eta_ti * ct) / (ci + eta_ti * ct);
  const float rp = (eta_ti * ci - ct) / (eta_ti * ci + ct);
  return {0.5f * (rs * rs + rp * rp), outside ? -ct : ct, eta_ti};
}

Rgb fresnel_conductor(float cos_i, const Rgb& eta, const Rgb& k) {
  const float c = std::fmin(std::fabs(cos_i), 1.0f);
  const float c2 = c * c, s2 = 1.0f - c2;
  Rgb out;
  for (int i = 0; i < 3; ++i) {
    // |n|² terms of the complex Snell law; a² + b² = |η² − sin²|.
    const float t0 = eta[i] * eta[i] - k[i] * k[i] - s2;
    const float a2b2 = std::sqrt(std::fmax(t0 * t0 + 4.0f * eta[i] * eta[i] * k[i] * k[i], 0.0f));
    const float a = std::sqrt(std::fmax(0.5f * (a2b2 + t0), 0.0f));
    const float t1 = a2b2 + c2, t2 = 2.0f * c * a;
    const float rs = (t1 - t2) / (t1 + t2);
    const float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
    const float rp = rs * (t3 - t4) / (t3 + t4);
    out[i] = 0.5f * (rs + rp);
  }
  return out;
}

float diffuse_fresnel_reflectance(float eta) {
  // Midpoint rule in μ = cos θ; F is smooth except at the critical angle, 4096 nodes give ~1e-6.
  constexpr int kNodes = 4096;
  double sum = 0;
  for (int i = 0; i < kNodes; ++i) {
    const double mu = (i + 0.5) / kNodes;
    sum += double(fresnel_dielectric(float(mu), eta).reflectance) * mu;
  }
  return float(2.0 * sum / kNodes);
}

}  // namespace clr::scene
