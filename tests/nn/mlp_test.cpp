// The MLP against its double twin: forward, inference, and parameter/input gradients checked by central finite
// differences of the twin (in double, so the differences themselves are accurate to ~1e-9).
#include "nn/mlp.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "nn/mlp_twin.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

struct MlpCase {
  const char* name;
  nn::MlpConfig cfg;
  std::size_t rows;
};

void PrintTo(const MlpCase& c, std::ostream* os) { *os << c.name; }

class MlpTest : public ClTest, public ::testing::WithParamInterface<MlpCase> {};

std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

TEST_P(MlpTest, ForwardInferAndGradientsMatchTwin) {
  const auto& pc = GetParam();
  nn::Gemm gemm(ctx(), nn::GemmChoice::Own);
  nn::Mlp mlp(ctx(), gemm, pc.cfg, 11);
  EXPECT_EQ(mlp.fused(), std::string(pc.name).rfind("Fused", 0) == 0);
  const std::size_t rows = pc.rows, I = pc.cfg.inputs, O = pc.cfg.outputs;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> x(rows * I), w(rows * O);
  for (auto& v : x) v = u(rng);
  for (auto& v : w) v = u(rng);
  // Non-zero biases so the bias path is exercised (the initialiser sets them to 0).
  auto params = mlp.params().read();
  for (std::size_t l = 0; l < mlp.layer_count(); ++l)
    for (std::size_t j = 0; j < mlp.fan_out(l); ++j) params[mlp.bias_offset(l) + j] = 0.3f * u(rng);
  mlp.params().write(params);

  MlpTwin twin{pc.cfg, to_double(params)};
  const auto xd = to_double(x), wd = to_double(w);

  cl::Buffer<float> dx_in(ctx(), std::span<const float>(x)), dw(ctx(), std::span<const float>(w));
  auto ctxt = mlp.forward_train(dx_in, rows);
  auto out = ctxt.output.read();
  std::vector<double> want(rows * O);
  for (std::size_t r = 0; r < rows; ++r) {
    const auto o = twin.forward_row(&xd[r * I]);
    std::copy(o.begin(), o.end(), want.begin() + long(r * O));
  }
  EXPECT_TRUE(all_near(std::span<const float>(out.data(), rows * O), std::span<const double>(want)));

  auto inf_host = with_canaries(rows * O);
  cl::Buffer<float> inf(ctx(), std::span<const float>(inf_host));
  mlp.infer(dx_in, rows, inf);
  inf.read(inf_host);
  EXPECT_TRUE(all_near(std::span<const float>(inf_host.data(), rows * O), std::span<const double>(want)));
  EXPECT_TRUE(canaries_intact(inf_host, rows * O));
  // Into rows further down a bigger buffer, as Network::infer writes its chunks: rows before stay untouched.
  const std::size_t out_row = 3;
  auto shifted_host = with_canaries((out_row + rows) * O);
  const auto before = shifted_host;
  cl::Buffer<float> shifted(ctx(), std::span<const float>(shifted_host));
  mlp.infer(dx_in, rows, shifted, out_row);
  shifted.read(shifted_host);
  EXPECT_TRUE(std::equal(before.begin(), before.begin() + long(out_row * O), shifted_host.begin()));
  EXPECT_TRUE(
      all_near(std::span<const float>(shifted_host.data() + out_row * O, rows * O), std::span<const double>(want)));
  EXPECT_TRUE(canaries_intact(shifted_host, (out_row + rows) * O));

  auto d_in_host = with_canaries(rows * I);
  cl::Buffer<float> d_in(ctx(), std::span<const float>(d_in_host));
  mlp.backward(ctxt, dw, &d_in);
  const auto g = mlp.grads().read();
  d_in.read(d_in_host);
  EXPECT_TRUE(canaries_intact(d_in_host, rows * I));

  const double h = 1e-6;
  for (std::size_t i = 0; i < twin.p.size(); ++i) {
    MlpTwin tp = twin, tm = twin;
    tp.p[i] += h;
    tm.p[i] -= h;
    const double fd = (tp.weighted_sum(xd, wd, rows) - tm.weighted_sum(xd, wd, rows)) / (2 * h);
    ASSERT_TRUE(near(g[i], fd)) << "d/dparam " << i;
  }
  for (std::size_t i = 0; i < rows * I; ++i) {
    auto xp = xd, xm = xd;
    xp[i] += h;
    xm[i] -= h;
    const double fd = (twin.weighted_sum(xp, wd, rows) - twin.weighted_sum(xm, wd, rows)) / (2 * h);
    ASSERT_TRUE(near(d_in_host[i], fd)) << "d/dinput " << i;
  }
}

nn::MlpConfig cfg(std::size_t in, std::size_t width, std::size_t hidden, std::size_t out, nn::OutputActivation act,
                  std::size_t chunk = 65536) {
  nn::MlpConfig c;
  c.inputs = in;
  c.width = width;
  c.hidden_layers = hidden;
  c.outputs = out;
  c.output_activation = act;
  c.max_chunk_rows = chunk;
  c.small_path = nn::MlpConfig::SmallPath::Fused;  // the fused kernel wherever it applies, so both paths are tested
  return c;
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, MlpTest,
    ::testing::Values(MlpCase{"DenseLayer", cfg(7, 1, 0, 5, nn::OutputActivation::None), 13},
                      MlpCase{"DenseAbs", cfg(6, 1, 0, 3, nn::OutputActivation::Abs), 9},
                      MlpCase{"DeepAbs", cfg(5, 36, 3, 3, nn::OutputActivation::Abs), 11},
                      MlpCase{"Chunked", cfg(4, 33, 2, 6, nn::OutputActivation::None, 7), 30},
                      // Shapes that take the one-launch fused kernel (widths multiples of 16, no output activation).
                      MlpCase{"FusedSmall", cfg(7, 16, 2, 16, nn::OutputActivation::None), 13},
                      MlpCase{"FusedChunked", cfg(5, 32, 1, 16, nn::OutputActivation::None, 7), 30}),
    [](const auto& p) { return std::string(p.param.name); });

// The I-Module's shape through both paths: the fused kernel and the per-layer GEMMs agree.
TEST_F(ClTest, FusedSmallMlpMatchesLayerPath) {
  nn::Gemm gemm(ctx(), nn::GemmChoice::Own);
  auto c = cfg(59, 64, 3, 32, nn::OutputActivation::None);
  nn::Mlp fused(ctx(), gemm, c, 4);
  c.small_path = nn::MlpConfig::SmallPath::Layers;
  nn::Mlp layered(ctx(), gemm, c, 4);
  ASSERT_TRUE(fused.fused());
  ASSERT_FALSE(layered.fused());
  const std::size_t rows = 1001;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> x(rows * 59), w(rows * 32);
  for (auto& v : x) v = u(rng);
  for (auto& v : w) v = u(rng);
  cl::Buffer<float> dx(ctx(), std::span<const float>(x)), dw(ctx(), std::span<const float>(w));
  auto a = fused.forward_train(dx, rows), b = layered.forward_train(dx, rows);
  EXPECT_TRUE(all_near(std::span<const float>(a.output.read()), std::span<const float>(b.output.read())));
  fused.backward(a, dw);
  layered.backward(b, dw);
  EXPECT_TRUE(all_near(std::span<const float>(fused.grads().read()), std::span<const float>(layered.grads().read())));
  auto out_host = with_canaries(rows * 32);
  cl::Buffer<float> out(ctx(), std::span<const float>(out_host));
  fused.infer(dx, rows, out);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, rows * 32));
  EXPECT_TRUE(all_near(std::span<const float>(out_host.data(), rows * 32), std::span<const float>(b.output.read())));
}

// The CLBlast backend (bias + activation as a separate pass) computes the same network as the own kernels.
TEST_F(ClTest, ClblastBackendMatchesOwn) {
  nn::Gemm own(ctx(), nn::GemmChoice::Own), blast(ctx(), nn::GemmChoice::CLBlast);
  const auto c = cfg(9, 40, 2, 3, nn::OutputActivation::Abs);
  nn::Mlp a(ctx(), own, c, 2), b(ctx(), blast, c, 2);
  const std::size_t rows = 77;
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> x(rows * c.inputs), w(rows * c.outputs);
  for (auto& v : x) v = u(rng);
  for (auto& v : w) v = u(rng);
  cl::Buffer<float> dx(ctx(), std::span<const float>(x)), dw(ctx(), std::span<const float>(w)),
      ga(ctx(), rows * c.inputs), gb(ctx(), rows * c.inputs);
  auto ca = a.forward_train(dx, rows), cb = b.forward_train(dx, rows);
  EXPECT_TRUE(all_near(std::span<const float>(cb.output.read()), std::span<const float>(ca.output.read())));
  a.backward(ca, dw, &ga);
  b.backward(cb, dw, &gb);
  EXPECT_TRUE(all_near(std::span<const float>(b.grads().read()), std::span<const float>(a.grads().read())));
  EXPECT_TRUE(all_near(std::span<const float>(gb.read()), std::span<const float>(ga.read())));
}

// He: weights uniform with variance 2/fan_in, zero biases; Torch (PyTorch's nn.Linear): weights and biases uniform
// in ±1/sqrt(fan_in); the output layer's scaled by output_init in both.
TEST_F(ClTest, InitialParametersFollowTheChosenInit) {
  nn::Gemm gemm(ctx(), nn::GemmChoice::Own);
  for (const auto init : {nn::WeightInit::He, nn::WeightInit::Torch}) {
    auto c = cfg(96, 128, 2, 3, nn::OutputActivation::Abs);
    c.init = init;
    c.output_init = 0.25f;
    nn::Mlp mlp(ctx(), gemm, c, 5);
    const auto p = mlp.params().read();
    const bool torch = init == nn::WeightInit::Torch;
    for (std::size_t l = 0; l < mlp.layer_count(); ++l) {
      const double scale = l + 1 == mlp.layer_count() ? 0.25 : 1.0;
      const double bound = scale * std::sqrt((torch ? 1.0 : 6.0) / double(mlp.fan_in(l)));
      const std::size_t w0 = mlp.bias_offset(l) - mlp.fan_in(l) * mlp.fan_out(l), b0 = mlp.bias_offset(l);
      double sum2 = 0;
      for (std::size_t i = w0; i < b0; ++i) {
        ASSERT_LE(std::abs(p[i]), bound) << "layer " << l;
        sum2 += double(p[i]) * p[i];
      }
      const double variance = sum2 / double(b0 - w0), want = bound * bound / 3;
      EXPECT_NEAR(variance, want, (l + 1 == mlp.layer_count() ? 0.5 : 0.1) * want) << "layer " << l;
      double bias_max = 0;
      for (std::size_t i = b0; i < b0 + mlp.fan_out(l); ++i) {
        ASSERT_LE(std::abs(p[i]), bound) << "bias of layer " << l;
        bias_max = std::max(bias_max, double(std::abs(p[i])));
      }
      if (torch)
        EXPECT_GT(bias_max, 0.1 * bound) << "layer " << l;
      else
        EXPECT_EQ(bias_max, 0.0) << "layer " << l;
    }
  }
}

}  // namespace
}  // namespace clr::test
