#pragma once
// Pearson's χ² goodness-of-fit of a BSDF's sample() against its pdf(), in the manner of Mitsuba's and pbrt's
// sampling tests: histogram of 10⁶ sampled directions on a (cos θ, φ) grid of odd resolution, expected counts from
// the pdf integrated over each cell, cells with expected counts below 5 pooled, p-value from the χ² distribution.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/pcg32.hpp"
#include "scene/bsdf.hpp"

namespace clr::test {

// Upper regularised incomplete gamma Q(a, x): series below a + 1, Lentz's continued fraction above.
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1.0 - sum * std::exp(log_prefix);
  }
  double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

struct SphereGrid {
  static constexpr int kTheta = 21, kPhi = 41;  // odd: no cell boundary on the normal or the plane of incidence
  static constexpr int kSub = 24;               // quadrature nodes per cell and axis

  static int cell(const scene::Vec3& w) {
    const double ct = std::clamp(double(w.z), -1.0, 1.0);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0) phi += 2 * M_PI;
    const int i = std::min(kTheta - 1, int((ct + 1) / 2 * kTheta));
    const int j = std::min(kPhi - 1, int(phi / (2 * M_PI) * kPhi));
    return i * kPhi + j;
  }
  // ∫ f dω over every cell (midpoint rule in cos θ and φ, where dω = d(cos θ) dφ, `sub` nodes per cell and axis).
  static std::vector<double> integrate(const std::function<double(const scene::Vec3&)>& f, int sub = kSub) {
    std::vector<double> out(kTheta * kPhi, 0.0);
    const double dct = 2.0 / (kTheta * sub), dphi = 2 * M_PI / (kPhi * sub);
    for (int i = 0; i < kTheta * sub; ++i) {
      const double ct = -1 + (i + 0.5) * dct, st = std::sqrt(std::max(0.0, 1 - ct * ct));
      for (int j = 0; j < kPhi * sub; ++j) {
        const double phi = (j + 0.5) * dphi;
        const scene::Vec3 w(float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct));
        out[std::size_t((i / sub) * kPhi + j / sub)] += f(w) * dct * dphi;
      }
    }
    return out;
  }
};

struct Chi2Result {
  double p_value = 0;
  int dof = 0;
  std::string problem;  // non-empty: samples where the pdf says none can be
};

// `sample` draws one direction (nullopt: no sample, e.g. a delta lobe or absorption), `pdf` is its claimed density;
// `sub` quadrature nodes per cell and axis integrate it (more for densities sharper than a sixth of a cell).
inline Chi2Result chi2_test(const std::function<std::optional<scene::Vec3>(Pcg32&)>& sample,
                            const std::function<double(const scene::Vec3&)>& pdf, std::size_t n, std::uint64_t seed,
                            int sub = SphereGrid::kSub) {
  std::vector<double> observed(SphereGrid::kTheta * SphereGrid::kPhi, 0.0);
  Pcg32 rng(0, seed);
  for (std::size_t s = 0; s < n; ++s)
    if (const auto w = sample(rng)) observed[std::size_t(SphereGrid::cell(*w))] += 1;
  auto expected = SphereGrid::integrate(pdf, sub);
  for (auto& e : expected) e *= double(n);

  // Pool the cells with small expected counts (smallest first) until each pool expects at least 5.
  std::vector<std::size_t> order(expected.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return expected[a] < expected[b]; });
  Chi2Result r;
  double chi2 = 0, pool_e = 0, pool_o = 0;
  int bins = 0;
  for (std::size_t k : order) {
    if (expected[k] == 0 && observed[k] > 0) {
      r.problem = "samples in a cell of zero pdf";
      return r;
    }
    if (expected[k] < 5) {
      pool_e += expected[k];
      pool_o += observed[k];
      if (pool_e >= 5) {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        ++bins;
        pool_e = pool_o = 0;
      }
      continue;
    }
    chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++bins;
  }
  if (pool_e > 0) {
    chi2 += (pool_o - pool_e) * (pool_o - pool_e) / std::max(pool_e, 1e-300);
    ++bins;
  }
  r.dof = bins - 1;
  r.p_value = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * chi2) : 1.0;
  return r;
}

// A BSDF's non-delta samples for a fixed wo against its pdf.
inline Chi2Result chi2_test(const scene::Bsdf& bsdf, const scene::Vec3& wo, std::size_t n, std::uint64_t seed) {
  const scene::Vec2 uv(0.5f);
  return chi2_test(
      [&](Pcg32& rng) -> std::optional<scene::Vec3> {
        const auto bs = bsdf.sample(uv, wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        if (!bs || bs->delta) return std::nullopt;
        return bs->wi;
      },
      [&](const scene::Vec3& w) { return double(bsdf.pdf(uv, wo, w)); }, n, seed);
}

}  // namespace clr::test
