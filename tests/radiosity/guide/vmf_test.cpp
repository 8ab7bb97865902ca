// kernels/vmf.cl and kernels/guide.cl against the double twin (nn/vmf_twin.hpp): χ² tests of the sampler for single
// lobes and mixtures, a uniformity test of sharp lobes in their own frame, normalisation, finiteness at the
// extremes, ∂log q and the KL / IKL gradients against central finite differences, and the IKL's sign.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

#include "radiosity/guide/vmf_mixture.hpp"
#include "radiosity/guide/vmf_twin.hpp"
#include "scene/chi2.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

using vmf::dvec3;

// The raw b of a lobe of concentration κ inside the clamp.
double raw_b(double kappa) { return std::log(kappa) - vmf::kLogKappa0; }

// Raw outputs of one lobe with weight logit a, concentration κ and mean direction (θ, φ) in the frame about the
// normal — the inverse of the activations (σ⁻¹ saturates at ±30 for the poles).
std::array<double, 4> lobe_raw(double a, double kappa, double theta, double phi) {
  const auto logit = [](double y) { return y <= 0 ? -30.0 : y >= 1 ? 30.0 : std::log(y / (1 - y)); };
  return {a, raw_b(kappa), logit(theta / M_PI) - vmf::kC0, logit(phi / (2 * M_PI))};
}

// A mixture whose only lobe with weight is lobe 0 (the others' softmax weights underflow to exactly 0).
std::vector<double> single_lobe(double kappa, double theta, double phi) {
  std::vector<double> raw(32, 0.0);
  for (int k = 0; k < 8; ++k) {
    const auto r = lobe_raw(k == 0 ? 0.0 : -1e4, 1.0, 1.0, 1.0);
    std::copy(r.begin(), r.end(), raw.begin() + 4 * k);
  }
  const auto r = lobe_raw(0.0, kappa, theta, phi);
  std::copy(r.begin(), r.end(), raw.begin());
  return raw;
}

std::vector<double> random_mixture(std::mt19937& rng, double max_log_kappa) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> raw(32);
  for (int k = 0; k < 8; ++k) {
    raw[4 * k] = 3 * u(rng) - 1.5;
    raw[4 * k + 1] = -2 + (max_log_kappa + 2) * u(rng);
    raw[4 * k + 2] = 6 * u(rng) - 3;
    raw[4 * k + 3] = 6 * u(rng) - 3;
  }
  return raw;
}

dvec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(dvec3(g(rng), g(rng), g(rng)));
}

// The kernels on a few points' raw outputs, in the frames about their normals (+z where not given).
class VmfDevice {
 public:
  VmfDevice(cl::Context& ctx, const std::vector<double>& raw, const std::vector<dvec3>& normals = {})
      : ctx_(&ctx),
        vmf_(ctx),
        points_(raw.size() / 32),
        raw_(ctx, std::span<const float>(to_float(raw))),
        normals_(ctx, points_ * 3) {
    std::vector<float> n;
    for (std::size_t m = 0; m < points_; ++m) {
      const dvec3 v = normals.empty() ? vmf::kUp : normals[m];
      n.insert(n.end(), {float(v.x), float(v.y), float(v.z)});
    }
    normals_.write(n);
    vmf_.decode(raw_, normals_, points_);
  }
  static std::vector<float> to_float(std::span<const double> v) { return {v.begin(), v.end()}; }

  std::vector<float> sample(const std::vector<float>& u) {
    const std::size_t samples = u.size() / 3 / points_;
    cl::Buffer<float> ub(*ctx_, std::span<const float>(u)), dirs(*ctx_, u.size());
    vmf_.sample(ub, samples, dirs);
    return dirs.read();
  }
  // q at dirs (3 floats each, samples per point).
  std::vector<float> pdf(const std::vector<float>& dirs) {
    const std::size_t n = dirs.size() / 3;
    std::vector<float> zero(n, 0.0f);
    cl::Buffer<float> d(*ctx_, std::span<const float>(dirs)), bp(*ctx_, std::span<const float>(zero)), pdf(*ctx_, n),
        q(*ctx_, n);
    vmf_.mixture_pdf(d, bp, n / points_, 0.0f, pdf, q);
    return q.read();
  }
  std::vector<float> dlogq(const std::vector<float>& dirs) {
    const std::size_t n = dirs.size() / 3;
    cl::Buffer<float> d(*ctx_, std::span<const float>(dirs)), out(*ctx_, n * 32);
    vmf_.dlogq(d, n / points_, out);
    return out.read();
  }
  radiosity::VmfMixture& vmf() { return vmf_; }
  const cl::Buffer<float>& raw() const { return raw_; }

 private:
  cl::Context* ctx_;
  radiosity::VmfMixture vmf_;
  std::size_t points_;
  cl::Buffer<float> raw_, normals_;
};

std::vector<float> uniforms(std::size_t n, std::uint64_t seed) {
  std::mt19937 rng{std::uint32_t(seed)};
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(3 * n);
  for (auto& x : v) x = u(rng);
  return v;
}

// χ² of device samples against the twin's pdf over the sphere, and the worst relative difference between the
// device's pdf at those samples and the twin's (a sample's pdf is pdf(ω)).
struct SamplerCheck {
  Chi2Result chi2;
  double worst_pdf_error = 0;
};

SamplerCheck check_sampler(cl::Context& ctx, const std::vector<double>& raw, std::uint64_t seed,
                           const dvec3& normal = vmf::kUp) {
  const auto lobes = vmf::decode(raw, normal);
  // Lobes narrower than a few grid cells need a finer quadrature of the expected counts (κ = 100 spans ~0.01 in
  // cos θ; a cell is 0.095).
  double kappa_max = 0;
  for (const auto& l : lobes)
    if (l.lambda > 0) kappa_max = std::max(kappa_max, l.kappa);
  constexpr std::size_t n = 1000000;
  VmfDevice dev(ctx, raw, {normal});
  const auto dirs = dev.sample(uniforms(n, seed));
  const auto q = dev.pdf(dirs);
  SamplerCheck c;
  for (std::size_t i = 0; i < n; i += 97) {
    const double want = vmf::pdf(lobes, glm::normalize(dvec3(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2])));
    c.worst_pdf_error = std::max(c.worst_pdf_error, std::abs(q[i] - want) / want);
  }
  std::size_t next = 0;
  c.chi2 = chi2_test(
      [&](Pcg32&) -> std::optional<scene::Vec3> {
        const std::size_t i = next++;
        return scene::Vec3(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]);
      },
      [&](const scene::Vec3& w) { return vmf::pdf(lobes, glm::normalize(dvec3(w))); }, n, seed,
      kappa_max > 30 ? 96 : SphereGrid::kSub);
  return c;
}

// 20 single lobes + 3 mixtures share α = 0.01 (Šidák).
const double kAlpha = 1 - std::pow(0.99, 1.0 / 23);

TEST_F(ClTest, VmfSingleLobesPassChi2) {
  int seed = 1;
  for (const double kappa : {1e-4, 1e-3, 1.0, 10.0, 100.0})
    for (const auto& [theta, phi] : {std::pair{0.0, 0.0}, {M_PI, 0.0}, {1.1, 4.0}, {M_PI / 2, 0.3}}) {
      const auto c = check_sampler(ctx(), single_lobe(kappa, theta, phi), std::uint64_t(seed++));
      EXPECT_TRUE(c.chi2.problem.empty()) << c.chi2.problem;
      EXPECT_GT(c.chi2.p_value, kAlpha) << "κ " << kappa << " θ " << theta << " φ " << phi;
      EXPECT_LT(c.worst_pdf_error, 5e-3) << "κ " << kappa << " θ " << theta;
    }
}

// The frame's normals: a random one, the axis where the frame takes its fallback tangent, and −z.
std::vector<dvec3> test_normals(std::mt19937& rng) {
  return {random_direction(rng), dvec3(0.48, 0.6, 0.64), -vmf::kUp};
}

TEST_F(ClTest, VmfMixturesPassChi2) {
  std::mt19937 rng(7);
  const auto normals = test_normals(rng);
  for (int i = 0; i < 3; ++i) {
    const auto raw = random_mixture(rng, std::log(100.0));
    const auto c = check_sampler(ctx(), raw, std::uint64_t(100 + i), normals[std::size_t(i)]);
    EXPECT_TRUE(c.chi2.problem.empty()) << c.chi2.problem;
    EXPECT_GT(c.chi2.p_value, kAlpha) << "mixture " << i;
    EXPECT_LT(c.worst_pdf_error, 5e-3) << "mixture " << i;
  }
}

// Too sharp for a sphere grid: in the lobe's own frame u = expm1(κ(cos θ − 1)) / expm1(−2κ) and φ are uniform.
TEST_F(ClTest, VmfSharpLobesAreUniformInTheirFrame) {
  constexpr std::size_t n = 400000;
  constexpr int bins = 10;
  for (const double kappa : {1e3, 1e4}) {
    const auto raw = single_lobe(kappa, 0.7, 2.0);
    const vmf::Lobe lobe = vmf::decode(raw)[0];
    const dvec3 a = std::abs(lobe.mu.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    const dvec3 t = glm::normalize(glm::cross(a, lobe.mu)), b = glm::cross(lobe.mu, t);
    VmfDevice dev(ctx(), raw);
    const auto dirs = dev.sample(uniforms(n, 11));
    std::vector<double> count(bins * bins, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const dvec3 w = glm::normalize(dvec3(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]));
      const double u = std::expm1(kappa * (glm::dot(w, lobe.mu) - 1)) / std::expm1(-2 * kappa);
      double phi = std::atan2(glm::dot(w, b), glm::dot(w, t));
      if (phi < 0) phi += 2 * M_PI;
      const int iu = std::clamp(int(u * bins), 0, bins - 1), ip = std::clamp(int(phi / (2 * M_PI) * bins), 0, bins - 1);
      count[std::size_t(iu * bins + ip)] += 1;
    }
    double chi2 = 0;
    const double expected = double(n) / (bins * bins);
    for (const double c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_GT(gamma_q(0.5 * (bins * bins - 1), 0.5 * chi2), 0.01 / 2) << "κ " << kappa << " χ² " << chi2;
  }
}

// ∫ q dω = 1: mixtures on a (cos θ, φ) midpoint grid, sharp lobes along log-spaced rings about their mean.
TEST_F(ClTest, VmfDensityIntegratesToOne) {
  std::mt19937 rng(5);
  const auto normals = test_normals(rng);
  for (int i = 0; i < 3; ++i) {
    const auto raw = random_mixture(rng, std::log(100.0));
    constexpr int nc = 8192, np = 512;  // fine in cos θ for lobes at the poles; φ is periodic
    std::vector<float> dirs;
    dirs.reserve(std::size_t(nc) * np * 3);
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b < np; ++b) {
        const double ct = -1 + (a + 0.5) * 2.0 / nc, st = std::sqrt(1 - ct * ct), phi = (b + 0.5) * 2 * M_PI / np;
        for (const double v : {st * std::cos(phi), st * std::sin(phi), ct}) dirs.push_back(float(v));
      }
    const auto q = VmfDevice(ctx(), raw, {normals[std::size_t(i)]}).pdf(dirs);
    double total = 0;
    for (const float v : q) total += double(v);
    EXPECT_NEAR(total * (2.0 / nc) * (2 * M_PI / np), 1.0, 1e-4) << "mixture " << i;
  }
  for (const double kappa : {1e-4, 1.0, 1e3, 1e4}) {
    const auto raw = single_lobe(kappa, 2.0, 1.0);
    const vmf::Lobe lobe = vmf::decode(raw)[0];
    const dvec3 t = glm::normalize(glm::cross(dvec3(0, 0, 1), lobe.mu)), b = glm::cross(lobe.mu, t);
    // r = 1 − cos θ on a log grid from 1e-10 to 2 (trapezoid in r), 64 directions a ring.
    constexpr int nr = 4000, np = 64;
    std::vector<double> r(nr + 1);
    for (int i = 0; i <= nr; ++i) r[std::size_t(i)] = i == 0 ? 0.0 : 2.0 * std::pow(1e-10 / 2.0, 1.0 - double(i) / nr);
    std::vector<float> dirs;
    for (const double ri : r) {
      const double ct = 1 - ri, st = std::sqrt(std::max(0.0, ri * (2 - ri)));
      for (int p = 0; p < np; ++p) {
        const double phi = (p + 0.5) * 2 * M_PI / np;
        const dvec3 w = st * std::cos(phi) * t + st * std::sin(phi) * b + ct * lobe.mu;
        for (int c = 0; c < 3; ++c) dirs.push_back(float(w[c]));
      }
    }
    const auto q = VmfDevice(ctx(), raw).pdf(dirs);
    double total = 0;
    for (int i = 0; i < nr; ++i) {
      double ring0 = 0, ring1 = 0;
      for (int p = 0; p < np; ++p) {
        ring0 += q[std::size_t(i * np + p)];
        ring1 += q[std::size_t((i + 1) * np + p)];
      }
      total += 0.5 * (ring0 + ring1) / np * 2 * M_PI * (r[std::size_t(i + 1)] - r[std::size_t(i)]);
    }
    EXPECT_NEAR(total, 1.0, 1e-4) << "κ " << kappa;
  }
}

// Concentrations past both ends of the clamp, poles and equator, ξ at 0 and 1 − 2⁻²⁴, ω = ±μ: finite, unit
// directions, and the pdf at the mean as the twin's.
TEST_F(ClTest, VmfStaysFiniteAtTheExtremes) {
  const double inf = std::numeric_limits<double>::infinity();
  const float top = 1.0f - std::ldexp(1.0f, -24);
  for (const double b : {-inf, raw_b(1e-8), raw_b(1e-4), 0.0, raw_b(1e4), 1e30, inf})
    for (const double c : {-30.0, 0.0, 30.0}) {
      std::vector<double> raw = single_lobe(1.0, 1.0, 1.0);
      raw[1] = b;
      raw[2] = c;
      VmfDevice dev(ctx(), raw);
      const std::vector<float> u = {0, 0, 0, top, top, top, 0, top, 0, top, 0, top};
      const auto dirs = dev.sample(u);
      for (std::size_t i = 0; i < dirs.size() / 3; ++i) {
        const double len = std::sqrt(dirs[3 * i] * dirs[3 * i] + dirs[3 * i + 1] * dirs[3 * i + 1] +
                                     dirs[3 * i + 2] * dirs[3 * i + 2]);
        EXPECT_NEAR(len, 1.0, 1e-5) << "b " << b << " c " << c << " sample " << i;
      }
      const dvec3 mu = vmf::decode(raw)[0].mu;
      std::vector<float> at = {float(mu.x), float(mu.y), float(mu.z), float(-mu.x), float(-mu.y), float(-mu.z)};
      const auto q = dev.pdf(at);
      for (const float v : q) EXPECT_TRUE(std::isfinite(v) && v >= 0.0f) << "b " << b << " c " << c;
      EXPECT_TRUE(near(q[0], vmf::pdf(raw, mu))) << "b " << b << " c " << c;
      for (const float g : dev.dlogq(at)) EXPECT_TRUE(std::isfinite(g)) << "b " << b << " c " << c;
    }
}

TEST_F(ClTest, VmfLogPdfGradientMatchesFiniteDifferences) {
  std::mt19937 rng(3);
  constexpr std::size_t points = 4, samples = 5;
  std::vector<double> raw;
  std::vector<dvec3> normals;
  for (std::size_t m = 0; m < points; ++m) {
    const auto r = random_mixture(rng, std::log(200.0));
    raw.insert(raw.end(), r.begin(), r.end());
    normals.push_back(random_direction(rng));
  }
  std::vector<float> dirs;
  for (std::size_t s = 0; s < points * samples; ++s) {
    const dvec3 w = random_direction(rng);
    for (int c = 0; c < 3; ++c) dirs.push_back(float(w[c]));
  }
  const auto grad = VmfDevice(ctx(), raw, normals).dlogq(dirs);
  for (std::size_t s = 0; s < points * samples; ++s) {
    const std::size_t m = s / samples;
    std::vector<double> r(raw.begin() + std::ptrdiff_t(m * 32), raw.begin() + std::ptrdiff_t(m * 32 + 32));
    const dvec3 w(dirs[3 * s], dirs[3 * s + 1], dirs[3 * s + 2]);
    for (int i = 0; i < 32; ++i) {
      const double h = 1e-5, keep = r[std::size_t(i)];
      r[std::size_t(i)] = keep + h;
      const double up = std::log(vmf::pdf(r, w, normals[m]));
      r[std::size_t(i)] = keep - h;
      const double down = std::log(vmf::pdf(r, w, normals[m]));
      r[std::size_t(i)] = keep;
      EXPECT_TRUE(near(grad[s * 32 + std::size_t(i)], (up - down) / (2 * h), {1e-2, 2e-3}))
          << "sample " << s << " raw " << i;
    }
  }
}

// One training step's samples for guide_loss, built on the host.
struct GuideBatch {
  std::size_t points, samples;
  std::vector<float> dirs, bsdf_pdf, pdf, weight, emitted, radiance;
  std::vector<int> lookup;
  std::vector<float> scattered;  // the N-Module's radiance at each point (RGB): F is its luminance
  std::vector<float> direct;     // the delta lights' term at each point (RGB), or empty: F is lum(scattered − direct)
};

double luminance(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

struct GuideResult {
  std::vector<float> d_raw;
  double loss;
};

GuideResult run_guide_loss(cl::Context& ctx, const std::vector<double>& raw, const GuideBatch& g, bool improved,
                           const std::vector<dvec3>& normals = {}) {
  VmfDevice dev(ctx, raw, normals);
  std::vector<float> radiance = g.radiance;
  if (radiance.empty()) radiance.assign(3, 0.0f);
  cl::Buffer<float> dirs(ctx, std::span<const float>(g.dirs)), bp(ctx, std::span<const float>(g.bsdf_pdf)),
      pdf(ctx, std::span<const float>(g.pdf)), w(ctx, std::span<const float>(g.weight)),
      e(ctx, std::span<const float>(g.emitted)), rad(ctx, std::span<const float>(radiance)),
      scattered(ctx, std::span<const float>(g.scattered));
  std::optional<cl::Buffer<float>> direct;
  if (!g.direct.empty()) direct.emplace(ctx, std::span<const float>(g.direct));
  cl::Buffer<int> lookup(ctx, std::span<const int>(g.lookup));
  auto out_host = with_canaries(g.points * 32);
  cl::Buffer<float> out(ctx, std::span<const float>(out_host));
  dev.vmf().loss({dirs, bp, pdf, w, e, lookup, rad, scattered, 1.0f, direct ? &*direct : nullptr}, g.samples, improved,
                 out);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, g.points * 32));
  out_host.resize(g.points * 32);
  return {out_host, dev.vmf().take().loss};
}

// The twin's view of point m's samples (delta samples left out; they still count in N).
std::vector<vmf::GuideSample> twin_samples(const GuideBatch& g, std::size_t m) {
  std::vector<vmf::GuideSample> out;
  for (std::size_t n = 0; n < g.samples; ++n) {
    const std::size_t s = m * g.samples + n;
    if (g.bsdf_pdf[s] < 0) continue;
    double rgb[3];
    for (int c = 0; c < 3; ++c) {
      rgb[c] = g.emitted[3 * s + std::size_t(c)];
      if (g.lookup[s] >= 0)
        rgb[c] += double(g.weight[3 * s + std::size_t(c)]) * g.radiance[3 * std::size_t(g.lookup[s]) + std::size_t(c)];
    }
    out.push_back({0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2], double(g.pdf[s]),
                   dvec3(g.dirs[3 * s], g.dirs[3 * s + 1], g.dirs[3 * s + 2])});
  }
  return out;
}

// Three points of six samples each with their lobes (raw) and normals: delta samples, dark samples, misses, and a
// last point whose N-Module radiance is far below what its samples saw (F is their estimate over N there).
GuideBatch random_guide_batch(std::mt19937& rng, std::vector<double>& raw, std::vector<dvec3>& normals) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  GuideBatch g{3, 6, {}, {}, {}, {}, {}, {}, {}, {}, {}};
  for (std::size_t m = 0; m < g.points; ++m) {
    const auto r = random_mixture(rng, std::log(50.0));
    raw.insert(raw.end(), r.begin(), r.end());
    normals.push_back(random_direction(rng));
  }
  int rows = 0;
  for (std::size_t s = 0; s < g.points * g.samples; ++s) {
    const dvec3 w = random_direction(rng);
    for (int c = 0; c < 3; ++c) g.dirs.push_back(float(w[c]));
    g.bsdf_pdf.push_back(s % 5 == 4 ? -1.0f : 0.1f + u(rng));  // every fifth sample is a delta lobe's
    g.pdf.push_back(0.05f + u(rng));
    const bool dark = s % 4 == 1, hit = s % 3 != 0;
    for (int c = 0; c < 3; ++c) {
      g.emitted.push_back(dark ? 0.0f : u(rng) * u(rng));
      g.weight.push_back(hit && !dark ? u(rng) : 0.0f);
    }
    g.lookup.push_back(hit ? rows++ : -1);
  }
  for (int i = 0; i < 3 * rows; ++i) g.radiance.push_back(2 * u(rng));
  for (std::size_t i = 0; i < 3 * g.points; ++i) g.scattered.push_back(0.1f + u(rng));
  std::fill(g.scattered.end() - 3, g.scattered.end(), 1e-6f);
  return g;
}

TEST_F(ClTest, GuideKlAndIklGradientsMatchFiniteDifferences) {
  std::mt19937 rng(9);
  std::vector<double> raw;
  std::vector<dvec3> normals;
  const GuideBatch g = random_guide_batch(rng, raw, normals);
  for (const bool improved : {false, true}) {
    const GuideResult got = run_guide_loss(ctx(), raw, g, improved, normals);
    double loss = 0;
    for (std::size_t m = 0; m < g.points; ++m) {
      const auto samples = twin_samples(g, m);
      std::vector<double> r(raw.begin() + std::ptrdiff_t(m * 32), raw.begin() + std::ptrdiff_t(m * 32 + 32));
      const double scale = 1.0 / double(g.points);
      const double F = luminance(&g.scattered[3 * m]);
      loss += scale * vmf::guide_loss(r, samples, F, g.samples, improved, normals[m]);
      for (int i = 0; i < 32; ++i) {
        const double h = 1e-5, keep = r[std::size_t(i)];
        r[std::size_t(i)] = keep + h;
        const double up = vmf::guide_loss(r, samples, F, g.samples, improved, normals[m]);
        r[std::size_t(i)] = keep - h;
        const double down = vmf::guide_loss(r, samples, F, g.samples, improved, normals[m]);
        r[std::size_t(i)] = keep;
        EXPECT_TRUE(near(got.d_raw[m * 32 + std::size_t(i)], scale * (up - down) / (2 * h), {1e-2, 1e-4}))
            << (improved ? "IKL" : "KL") << " point " << m << " raw " << i;
      }
    }
    EXPECT_TRUE(near(got.loss, loss)) << (improved ? "IKL" : "KL");
  }
}

// One lit sample (t = 1) and one dark one, F = 1/(2p̃): p = 2p̃ at the lit sample, and p̃ sets p/q by hand. IKL's
// gradient is KL's where p > q and its negative where p < q; at p = q the IKL loss vanishes and the magnitude is KL's.
// A scene's delta lights add their next-event term D to L_α but to no sampled direction, so the guide's target
// density is normalised by L_α − D: the loss given (L_α, D) is the loss given L_α − D and no D, and differs from
// the one given L_α alone.
TEST_F(ClTest, GuideNormaliserLeavesOutTheDeltaLightsTerm) {
  std::mt19937 rng(11);
  std::vector<double> raw;
  std::vector<dvec3> normals;
  GuideBatch with_direct = random_guide_batch(rng, raw, normals);
  GuideBatch less_direct = with_direct;
  for (std::size_t i = 0; i < with_direct.scattered.size(); ++i) {
    with_direct.direct.push_back(0.5f * with_direct.scattered[i]);
    less_direct.scattered[i] = with_direct.scattered[i] - with_direct.direct[i];
  }
  for (const bool improved : {false, true}) {
    const GuideResult got = run_guide_loss(ctx(), raw, with_direct, improved, normals);
    const GuideResult want = run_guide_loss(ctx(), raw, less_direct, improved, normals);
    GuideBatch ignoring = with_direct;
    ignoring.direct.clear();
    const GuideResult ignored = run_guide_loss(ctx(), raw, ignoring, improved, normals);
    EXPECT_TRUE(near(got.loss, want.loss, {1e-5, 1e-7})) << got.loss << " vs " << want.loss;
    // The first point's gradient (the last point's F is its samples' bound, which D does not move).
    EXPECT_FALSE(all_near(std::span<const float>(ignored.d_raw).first(32), std::span<const float>(want.d_raw).first(32),
                          {1e-2, 1e-7}))
        << "the test's D must matter";
    for (std::size_t i = 0; i < want.d_raw.size(); ++i)
      EXPECT_TRUE(near(got.d_raw[i], want.d_raw[i], {1e-4, 1e-7})) << (improved ? "IKL" : "KL") << " raw " << i;
  }
}

TEST_F(ClTest, IklFlipsTheKlGradientWherePIsBelowQ) {
  std::mt19937 rng(4);
  const auto raw = random_mixture(rng, std::log(30.0));
  const dvec3 w = random_direction(rng);
  const double q = vmf::pdf(raw, w);
  for (const double ratio : {4.0, 0.25, 1.0}) {  // p / q
    GuideBatch g{1, 2, {}, {1.0f, 1.0f}, {}, {}, {}, {}, {-1, -1}, {}, {}};
    for (int i = 0; i < 2; ++i)
      for (int c = 0; c < 3; ++c) g.dirs.push_back(float(w[c]));
    g.pdf = {float(ratio * q / 2), 1.0f};
    g.scattered.assign(3, float(1 / (ratio * q)));  // grey: its luminance is F
    g.emitted = {1, 1, 1, 0, 0, 0};
    g.weight.assign(6, 0.0f);
    const auto kl = run_guide_loss(ctx(), raw, g, false), ikl = run_guide_loss(ctx(), raw, g, true);
    const double sign = ratio > 1 ? 1.0 : -1.0;
    for (int i = 0; i < 32; ++i) {
      if (ratio == 1.0)
        EXPECT_TRUE(near(std::abs(ikl.d_raw[std::size_t(i)]), std::abs(kl.d_raw[std::size_t(i)]))) << "raw " << i;
      else
        EXPECT_TRUE(near(ikl.d_raw[std::size_t(i)], sign * kl.d_raw[std::size_t(i)]))
            << "p/q " << ratio << " raw " << i;
    }
    // (1/N) p/p̃ = 1: the loss is log(p/q) itself.
    EXPECT_TRUE(near(kl.loss, std::log(ratio), {1e-3, 1e-4})) << "p/q " << ratio;
    EXPECT_TRUE(near(ikl.loss, std::abs(std::log(ratio)), {1e-3, 1e-4})) << "p/q " << ratio;
  }
}

}  // namespace
}  // namespace clr::test
