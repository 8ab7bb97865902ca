#pragma once
// Double-precision host twin of kernels/vmf.cl and kernels/guide.cl: the lobe activations, the mixture's log-pdf,
// one-lobe sampling, and the I-Module's KL / IKL loss of one point (whose raw gradient the tests take by central
// finite differences).
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace clr::test::vmf {

inline constexpr int kLobes = 8, kRaw = 32;
inline constexpr double kLogKappaMin = -9.2103403719761836, kLogKappaMax = 9.2103403719761836;  // κ ∈ [1e-4, 1e4]
// The offsets on the raw b and c: raw 0 is a lobe of κ = 3 at θ = 36° (σ(c₀) = 0.2) from the frame's normal.
inline constexpr double kMaxWeight = 1024;
inline constexpr double kLogKappa0 = 1.0986122886681098, kC0 = -1.3862943611198906;

using dvec3 = glm::dvec3;

struct Lobe {
  double lambda, kappa;
  dvec3 mu;
};

inline double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

inline const dvec3 kUp(0, 0, 1);

// The tangent frame about n (vmf_frame): continuous in n away from ±(0.48, 0.6, 0.64).
inline void frame(const dvec3& n, dvec3& t, dvec3& s) {
  dvec3 c = glm::cross(dvec3(0.48, 0.6, 0.64), n);
  if (glm::dot(c, c) < 1e-4) c = glm::cross(dvec3(0.8, -0.6, 0.0), n);
  t = glm::normalize(c);
  s = glm::cross(n, t);
}

inline std::array<Lobe, kLobes> decode(std::span<const double> raw, const dvec3& n = kUp) {
  std::array<Lobe, kLobes> lobes;
  dvec3 t, s;
  frame(n, t, s);
  double amax = raw[0];
  for (int k = 1; k < kLobes; ++k) amax = std::max(amax, raw[4 * k]);
  double sum = 0;
  for (int k = 0; k < kLobes; ++k) sum += std::exp(raw[4 * k] - amax);
  for (int k = 0; k < kLobes; ++k) {
    const double theta = M_PI * sigmoid(raw[4 * k + 2] + kC0), phi = 2 * M_PI * sigmoid(raw[4 * k + 3]);
    lobes[k] = {std::exp(raw[4 * k] - amax) / sum,
                std::exp(std::clamp(raw[4 * k + 1] + kLogKappa0, kLogKappaMin, kLogKappaMax)),
                std::sin(theta) * std::cos(phi) * t + std::sin(theta) * std::sin(phi) * s + std::cos(theta) * n};
  }
  return lobes;
}

// v(ω) = κ / (2π (1 − e^{−2κ})) · e^{κ (μ·ω − 1)}
inline double lobe_pdf(const Lobe& l, const dvec3& w) {
  return l.kappa / (2 * M_PI * -std::expm1(-2 * l.kappa)) * std::exp(l.kappa * (glm::dot(l.mu, w) - 1));
}

inline double pdf(const std::array<Lobe, kLobes>& lobes, const dvec3& w) {
  double q = 0;
  for (const Lobe& l : lobes) q += l.lambda * lobe_pdf(l, w);
  return q;
}

inline double pdf(std::span<const double> raw, const dvec3& w, const dvec3& n = kUp) { return pdf(decode(raw, n), w); }

// cos θ about μ from the inverse CDF, φ uniform; any orthonormal frame around μ (the χ² tests bin directions).
inline dvec3 sample_lobe(const Lobe& l, double u1, double u2) {
  const double ct = std::clamp(1 + std::log1p(u1 * std::expm1(-2 * l.kappa)) / l.kappa, -1.0, 1.0);
  const double st = std::sqrt(std::max(0.0, 1 - ct * ct)), phi = 2 * M_PI * u2;
  const dvec3 a = std::abs(l.mu.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  const dvec3 t = glm::normalize(glm::cross(a, l.mu)), b = glm::cross(l.mu, t);
  return st * std::cos(phi) * t + st * std::sin(phi) * b + ct * l.mu;
}

// One point's samples as guide_loss reads them: target luminance t = lum(f·cos·L_i), the density p̃ the sample was
// drawn with, and its direction; delta samples are left out by the caller (they count in N only).
struct GuideSample {
  double target, pdf;
  dvec3 w;
};

// (1/N) Σ p/p̃ · log(p/q) (KL) or its absolute value (IKL), p = t/F with F the N-Module's radiance at the point
// (bounded below by the samples' own estimate over kMaxWeight, guide.cl's GUIDE_MAX_WEIGHT), p and p̃ constants: its
// gradient w.r.t. raw is guide_loss's.
inline double guide_loss(std::span<const double> raw, std::span<const GuideSample> s, double f_net, std::size_t n_total,
                         bool improved, const dvec3& n = kUp) {
  double f_samples = 0;
  for (const auto& x : s) f_samples += x.target / x.pdf;
  const double F = std::max(f_net, f_samples / (double(n_total) * kMaxWeight));
  if (!(F > 0)) return 0;
  double loss = 0;
  for (const auto& x : s) {
    const double p = x.target / F;
    if (p <= 0) continue;
    const double log_ratio = std::log(p) - std::log(pdf(raw, x.w, n));
    loss += p / x.pdf / double(n_total) * (improved ? std::abs(log_ratio) : log_ratio);
  }
  return loss;
}

}  // namespace clr::test::vmf
