// The MLP against its double twin: forward, inference, and parameter/input gradients checked by central finite
// differences of the twin (in double, so the differences themselves are accurate to ~1e-9).
#include "nn/mlp.hpp"

#include <gtest/gtest.h>

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
  return c;
}

INSTANTIATE_TEST_SUITE_P(Shapes, MlpTest,
                         ::testing::Values(MlpCase{"DenseLayer", cfg(7, 1, 0, 5, nn::OutputActivation::None), 13},
                                           MlpCase{"DenseAbs", cfg(6, 1, 0, 3, nn::OutputActivation::Abs), 9},
                                           MlpCase{"DeepAbs", cfg(5, 36, 3, 3, nn::OutputActivation::Abs), 11},
                                           MlpCase{"Chunked", cfg(4, 33, 2, 6, nn::OutputActivation::None, 7), 30}),
                         [](const auto& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace clr::test
