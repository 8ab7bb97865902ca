// Adam and the loss kernels against double-precision twins; non-finite values are dropped and counted.
#include "nn/adam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "nn/loss.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

struct AdamTwin {
  nn::AdamConfig c;
  std::vector<double> m, v;
  std::uint64_t t = 0;
  void step(std::vector<double>& p, const std::vector<double>& g, const std::vector<bool>* active = nullptr) {
    ++t;
    const double lr = c.learning_rate_at(t);
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (active && !(*active)[i]) continue;
      if (!std::isfinite(g[i])) continue;
      m[i] = c.beta1 * m[i] + (1 - double(c.beta1)) * g[i];
      v[i] = c.beta2 * v[i] + (1 - double(c.beta2)) * g[i] * g[i];
      const double mh = m[i] / (1 - std::pow(double(c.beta1), double(t)));
      const double vh = v[i] / (1 - std::pow(double(c.beta2), double(t)));
      p[i] -= lr * (mh / (std::sqrt(vh) + c.epsilon) + c.weight_decay * p[i]);
    }
  }
};

TEST(AdamSchedule, ExponentialDecayAfterStart) {
  nn::AdamConfig c;
  c.learning_rate = 1.0f;
  c.decay = 0.5f;
  c.decay_start = 100;
  c.decay_interval = 10;
  EXPECT_EQ(c.learning_rate_at(1), 1.0f);
  EXPECT_EQ(c.learning_rate_at(100), 1.0f);
  EXPECT_EQ(c.learning_rate_at(109), 1.0f);
  EXPECT_EQ(c.learning_rate_at(110), 0.5f);
  EXPECT_EQ(c.learning_rate_at(130), 0.125f);
}

TEST_F(ClTest, AdamDenseMatchesTwinAndDropsNonFinite) {
  const std::size_t n = 1001;
  nn::AdamConfig cfg;
  cfg.learning_rate = 0.01f;
  cfg.weight_decay = 0.1f;
  nn::Adam adam(ctx(), n, cfg);
  AdamTwin twin{cfg, std::vector<double>(n), std::vector<double>(n)};
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(n), g(n);
  for (auto& x : p) x = u(rng);
  std::vector<double> pd(p.begin(), p.end());
  cl::Buffer<float> dp(ctx(), std::span<const float>(p)), dg(ctx(), n);
  for (int step = 0; step < 5; ++step) {
    for (auto& x : g) x = u(rng);
    if (step == 2) g[17] = std::numeric_limits<float>::quiet_NaN();
    if (step == 3) g[400] = std::numeric_limits<float>::infinity();
    dg.write(g);
    adam.step(dp, dg);
    twin.step(pd, std::vector<double>(g.begin(), g.end()));
    EXPECT_TRUE(all_near(std::span<const float>(dp.read()), std::span<const double>(pd))) << "step " << step;
    // The step consumed the gradient.
    for (float x : dg.read()) ASSERT_EQ(x, 0.0f);
  }
  EXPECT_EQ(adam.non_finite_gradients(), 2u);
}

TEST_F(ClTest, AdamSparseTouchesOnlyFlaggedEntries) {
  const std::size_t entries = 300, features = 4, n = entries * features;
  nn::AdamConfig cfg;
  cfg.learning_rate = 0.05f;
  nn::Adam adam(ctx(), n, cfg);
  AdamTwin twin{cfg, std::vector<double>(n), std::vector<double>(n)};
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(n), g(n);
  for (auto& x : p) x = u(rng);
  std::vector<double> pd(p.begin(), p.end());
  cl::Buffer<float> dp(ctx(), std::span<const float>(p)), dg(ctx(), n);
  cl::Buffer<std::uint8_t> touched(ctx(), entries);
  for (int step = 0; step < 4; ++step) {
    std::vector<std::uint8_t> flags(entries);
    std::vector<bool> active(n);
    std::fill(g.begin(), g.end(), 0.0f);
    for (std::size_t e = 0; e < entries; ++e) {
      flags[e] = (e * 7 + std::size_t(step)) % 3 == 0;
      for (std::size_t f = 0; f < features; ++f) {
        active[e * features + f] = flags[e];
        if (flags[e]) g[e * features + f] = u(rng);
      }
    }
    touched.write(flags);
    dg.write(g);
    adam.step_sparse(dp, dg, touched, features);
    twin.step(pd, std::vector<double>(g.begin(), g.end()), &active);
    EXPECT_TRUE(all_near(std::span<const float>(dp.read()), std::span<const double>(pd))) << "step " << step;
    for (auto f : touched.read()) ASSERT_EQ(f, 0) << "flags are cleared by the step";
  }
}

TEST_F(ClTest, AdamSparseFixedPointGradient) {
  const std::size_t entries = 64, features = 2, n = entries * features;
  nn::AdamConfig cfg;
  nn::Adam adam(ctx(), n, cfg);
  AdamTwin twin{cfg, std::vector<double>(n), std::vector<double>(n)};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<float> p(n, 0.5f);
  std::vector<double> pd(p.begin(), p.end()), g(n);
  std::vector<std::int64_t> fixed(n);
  std::vector<bool> active(n);
  std::vector<std::uint8_t> flags(entries);
  for (std::size_t e = 0; e < entries; ++e) {
    flags[e] = e % 2;
    for (std::size_t f = 0; f < features; ++f) {
      const std::size_t i = e * features + f;
      active[i] = flags[e];
      fixed[i] = flags[e] ? std::int64_t(std::llround(u(rng) * 0x1p30)) : 0;  // gradients of order 2^-10
      g[i] = double(fixed[i]) * 0x1p-40;
    }
  }
  cl::Buffer<float> dp(ctx(), std::span<const float>(p));
  cl::Buffer<std::int64_t> dg(ctx(), std::span<const std::int64_t>(fixed));
  cl::Buffer<std::uint8_t> touched(ctx(), std::span<const std::uint8_t>(flags));
  adam.step_sparse_fixed(dp, dg, touched, features);
  twin.step(pd, g, &active);
  EXPECT_TRUE(all_near(std::span<const float>(dp.read()), std::span<const double>(pd)));
  for (auto v : dg.read()) ASSERT_EQ(v, 0) << "the step consumes the gradient";
}

// The denominator's power: 0 (L2), 1 (relative L2) and a value between, as a fading relative loss passes.
class LossTest : public ClTest, public ::testing::WithParamInterface<float> {};

TEST_P(LossTest, ValueAndGradientMatchTwin) {
  const float power = GetParam();
  const std::size_t n = 777;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<float> pred(n), target(n);
  for (auto& x : pred) x = u(rng);
  for (auto& x : target) x = u(rng);
  pred[10] = std::numeric_limits<float>::quiet_NaN();
  target[20] = std::numeric_limits<float>::infinity();
  const float scale = 1.0f / float(n);
  double want = 0;
  std::vector<double> want_grad(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 10 || i == 20) continue;
    const double r = double(pred[i]) - double(target[i]);
    const double den = std::pow(double(pred[i]) * pred[i] + 0.01, double(power));
    want += scale * r * r / den;
    want_grad[i] = scale * 2 * r / den;  // the denominator is a stop-gradient constant
  }
  cl::Buffer<float> dp(ctx(), std::span<const float>(pred)), dt(ctx(), std::span<const float>(target));
  auto grad_host = with_canaries(n);
  cl::Buffer<float> dg(ctx(), std::span<const float>(grad_host));
  nn::Loss loss(ctx());
  loss.evaluate(dp, dt, n, scale, power, dg);
  const auto v = loss.take();
  dg.read(grad_host);
  EXPECT_TRUE(near(v.loss, want));
  EXPECT_EQ(v.non_finite, 2u);
  EXPECT_TRUE(all_near(std::span<const float>(grad_host.data(), n), std::span<const double>(want_grad)));
  EXPECT_TRUE(canaries_intact(grad_host, n));
  // take() resets: a second evaluation over the same data gives the same value, not twice it.
  loss.evaluate(dp, dt, n, scale, power, dg);
  EXPECT_TRUE(near(loss.take().loss, want));
}

INSTANTIATE_TEST_SUITE_P(Powers, LossTest, ::testing::Values(0.0f, 0.37f, 1.0f));

}  // namespace
}  // namespace clr::test
