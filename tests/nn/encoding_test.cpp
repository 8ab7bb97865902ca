// Hash grid, SH and the composed encoder against their double twins, with finite-difference gradient checks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

#include "nn/encoder.hpp"
#include "nn/encoding_twin.hpp"
#include "nn/gemm.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

nn::HashGridConfig small_grid() {
  nn::HashGridConfig g;
  g.levels = 4;
  g.features = 2;
  g.log2_table = 8;  // T = 256: levels of resolution 2 and 4 are dense (27, 125 vertices), 8 and 16 are hashed
  g.base_resolution = 2;
  g.growth = 2.0;
  g.bbox_lo = {-1.0f, 0.0f, 2.0f};
  g.bbox_hi = {1.0f, 3.0f, 2.5f};
  return g;
}

// Random positions covering the box and a margin outside it (clamped to the boundary by the encoding).
std::vector<float> positions(std::size_t rows, const nn::HashGridConfig& g, std::size_t ld, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<float> p(rows * ld, 0.0f);
  for (std::size_t r = 0; r < rows; ++r)
    for (int i = 0; i < 3; ++i) {
      const float e = g.bbox_hi[i] - g.bbox_lo[i];
      p[r * ld + i] = std::uniform_real_distribution<float>(g.bbox_lo[i] - 0.1f * e, g.bbox_hi[i] + 0.1f * e)(rng);
    }
  return p;
}

TEST(HashGridLevels, DenseWhileVerticesFitTheTable) {
  const auto levels = nn::hashgrid_levels(small_grid());
  ASSERT_EQ(levels.size(), 4u);
  EXPECT_EQ(levels[0].resolution, 2u);
  EXPECT_TRUE(levels[0].dense);
  EXPECT_EQ(levels[0].entries, 27u);
  EXPECT_TRUE(levels[1].dense);
  EXPECT_EQ(levels[1].offset, 27u);
  EXPECT_FALSE(levels[2].dense);
  EXPECT_EQ(levels[2].entries, 256u);
  EXPECT_EQ(levels[3].resolution, 16u);
  nn::HashGridConfig g = small_grid();
  g.growth = 1.5;  // floor(2 · 1.5^l): 2, 3, 4, 6
  const auto l2 = nn::hashgrid_levels(g);
  EXPECT_EQ(l2[1].resolution, 3u);
  EXPECT_EQ(l2[3].resolution, 6u);
}

class HashGridTest : public ClTest, public ::testing::WithParamInterface<bool> {};

TEST_P(HashGridTest, ForwardAndTableGradientMatchTwin) {
  auto cfg = small_grid();
  cfg.deterministic = GetParam();
  nn::HashGrid grid(ctx(), cfg, {}, 3);
  const std::size_t rows = 200, ld = 5, F = cfg.features, D = grid.outputs();
  // Larger table values than the initialiser's ±1e-4, so the tolerance's absolute floor does not hide errors.
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> table(grid.params().size());
  for (auto& v : table) v = u(rng);
  grid.params().write(table);
  const std::vector<double> tabled(table.begin(), table.end());
  const auto pos = positions(rows, cfg, ld, 8);
  cl::Buffer<float> dpos(ctx(), std::span<const float>(pos));

  // Output written into columns [2, 2 + D) of a wider matrix, as the encoder does.
  const std::size_t out_ld = D + 3, col = 2;
  auto out_host = with_canaries(rows * out_ld, 7.0f);
  cl::Buffer<float> out(ctx(), std::span<const float>(out_host));
  grid.forward(dpos, 0, ld, rows, out, col, out_ld);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, rows * out_ld));
  for (std::size_t r = 0; r < rows; ++r) {
    const auto want = grid_encode(cfg, grid.levels(), tabled, &pos[r * ld]);
    EXPECT_TRUE(all_near(std::span<const float>(&out_host[r * out_ld + col], D), std::span<const double>(want)))
        << "row " << r;
    EXPECT_EQ(out_host[r * out_ld], 7.0f);  // columns outside the encoding untouched
  }

  // L = Σ w · encoding. The encoding is linear in the table, so dL/dtable is exactly Σ w · (interpolation
  // weight) and the central difference of the double twin reproduces it up to double rounding: the float
  // tolerance only has to absorb the device's float32 weights and atomic summation order. (W.r.t. position the
  // encoding is piecewise linear, its gradient piecewise constant, which is why positions get no FD check.)
  std::vector<float> w(rows * out_ld);
  for (auto& v : w) v = u(rng);
  cl::Buffer<float> dw(ctx(), std::span<const float>(w));
  grid.backward(dpos, 0, ld, rows, dw, col, out_ld);
  const auto g = grid.gradient();
  const auto touched = grid.touched().read();
  auto loss = [&](const std::vector<double>& t) {
    double L = 0;
    for (std::size_t r = 0; r < rows; ++r) {
      const auto e = grid_encode(cfg, grid.levels(), t, &pos[r * ld]);
      for (std::size_t j = 0; j < D; ++j) L += double(w[r * out_ld + col + j]) * e[j];
    }
    return L;
  };
  std::vector<bool> reached(grid.entries(), false);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t l = 0; l < cfg.levels; ++l)
      for (const auto& c : grid_corners(cfg, grid.levels()[l], &pos[r * ld]))
        if (c.weight != 0.0) reached[c.entry] = true;
  const double h = 1e-3;  // linear: any step gives the same difference
  for (std::size_t i = 0; i < tabled.size(); ++i) {
    auto tp = tabled, tm = tabled;
    tp[i] += h;
    tm[i] -= h;
    ASSERT_TRUE(near(g[i], (loss(tp) - loss(tm)) / (2 * h))) << "d/dtable " << i;
  }
  for (std::size_t e = 0; e < reached.size(); ++e) ASSERT_EQ(bool(touched[e]), reached[e]) << "touched flag " << e;
  (void)F;
}

// Lazy Adam updates only the entries a batch reached; dense Adam (PyTorch's, the NR authors' code) every entry, so
// an entry reached only by the first batch keeps moving on its momentum in the second step. Both against a double
// Adam twin fed the device's own gradients, at the table's own rate (learning_rate_factor times the network's).
TEST_P(HashGridTest, DenseAdamMovesTheEntriesABatchMissed) {
  const std::pair<bool, float> cases[] = {{false, 1.0f}, {true, 1.0f}, {false, 3.0f}};
  for (const auto& [dense, factor] : cases) {
    auto cfg = small_grid();
    cfg.deterministic = GetParam();
    cfg.dense_adam = dense;
    cfg.learning_rate_factor = factor;
    nn::AdamConfig adam;
    adam.learning_rate = 0.01f;
    nn::HashGrid grid(ctx(), cfg, adam, 3);
    const auto table0 = grid.params().read();
    std::vector<double> p(table0.begin(), table0.end()), m(p.size()), v(p.size());
    const std::size_t rows = 6, ld = 3, D = grid.outputs(), F = cfg.features;
    std::size_t moved_untouched = 0;
    for (int step = 1; step <= 2; ++step) {
      const auto pos = positions(rows, cfg, ld, 20 + step);  // another handful of points each step
      cl::Buffer<float> dpos(ctx(), std::span<const float>(pos));
      std::vector<float> w(rows * D, 1.0f);
      cl::Buffer<float> dw(ctx(), std::span<const float>(w));
      grid.backward(dpos, 0, ld, rows, dw, 0, D);
      const auto g = grid.gradient();
      const auto touched = grid.touched().read();
      const auto before = grid.params().read();
      grid.adam_step();
      const auto after = grid.params().read();
      const double lr = double(adam.learning_rate) * factor, c1 = 1 - std::pow(double(adam.beta1), step),
                   c2 = 1 - std::pow(double(adam.beta2), step);
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (!dense && !touched[i / F]) continue;
        m[i] = adam.beta1 * m[i] + (1 - double(adam.beta1)) * g[i];
        v[i] = adam.beta2 * v[i] + (1 - double(adam.beta2)) * double(g[i]) * g[i];
        p[i] -= lr * (m[i] / c1) / (std::sqrt(v[i] / c2) + adam.epsilon);
        if (!touched[i / F] && after[i] != before[i]) ++moved_untouched;
      }
      ASSERT_TRUE(all_near(std::span<const float>(after), std::span<const double>(p)))
          << "step " << step << ", dense " << dense << ", factor " << factor;
    }
    if (dense)
      EXPECT_GT(moved_untouched, 0u) << "entries reached only by the first batch move on their momentum";
    else
      EXPECT_EQ(moved_untouched, 0u);
  }
}

// Fixed-point (deterministic, int64 atomics) and float CAS accumulation of the table gradient.
INSTANTIATE_TEST_SUITE_P(Accumulation, HashGridTest, ::testing::Values(true, false),
                         [](const auto& p) { return p.param ? std::string("FixedPoint") : std::string("FloatCas"); });

TEST_F(ClTest, ShForwardAndGradientMatchTwin) {
  const std::size_t rows = 50, ld = 4;
  std::mt19937 rng(6);
  std::normal_distribution<float> n01;
  std::vector<float> dirs(rows * ld, 0.0f), w(rows * 16);
  for (std::size_t r = 0; r < rows; ++r) {
    float v[3] = {n01(rng), n01(rng), n01(rng)};
    const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i) dirs[r * ld + i] = v[i] / len;
  }
  for (auto& x : w) x = n01(rng);
  cl::Buffer<float> din(ctx(), std::span<const float>(dirs)), dw(ctx(), std::span<const float>(w));
  auto out_host = with_canaries(rows * 16);
  cl::Buffer<float> out(ctx(), std::span<const float>(out_host));
  const auto& program = ctx().program({"sh.cl"});
  program.kernel("sh_forward").args(nn::u32(rows), din, 0u, nn::u32(ld), out, 0u, 16u).launch(rows, 64);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, rows * 16));
  auto grad_host = with_canaries(rows * 3);
  cl::Buffer<float> grad(ctx(), std::span<const float>(grad_host));
  program.kernel("sh_backward").args(nn::u32(rows), din, 0u, nn::u32(ld), dw, 0u, 16u, grad, 0u, 3u).launch(rows, 64);
  grad.read(grad_host);
  EXPECT_TRUE(canaries_intact(grad_host, rows * 3));
  for (std::size_t r = 0; r < rows; ++r) {
    const double* none = nullptr;
    (void)none;
    const double x = dirs[r * ld], y = dirs[r * ld + 1], z = dirs[r * ld + 2];
    const auto want = sh16(x, y, z);
    EXPECT_TRUE(all_near(std::span<const float>(&out_host[r * 16], 16), std::span<const double>(want)));
    // Smooth polynomials: central differences in double with h = 1e-6 are accurate to ~1e-10.
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      double p[3] = {x, y, z}, m[3] = {x, y, z};
      p[i] += h;
      m[i] -= h;
      const auto sp = sh16(p[0], p[1], p[2]), sm = sh16(m[0], m[1], m[2]);
      double fd = 0;
      for (int j = 0; j < 16; ++j) fd += double(w[r * 16 + j]) * (sp[j] - sm[j]) / (2 * h);
      EXPECT_TRUE(near(grad_host[r * 3 + i], fd)) << "row " << r << " axis " << i;
    }
  }
}

TEST_F(ClTest, EncoderConcatenatesItsParts) {
  nn::EncoderConfig cfg;
  cfg.grid = small_grid();
  cfg.roughness = true;
  nn::Encoder enc(ctx(), cfg, {}, 1);
  const std::size_t rows = 40, D = enc.outputs(), G = enc.grid()->outputs();
  ASSERT_EQ(D, G + 16 + 16 + 3 + 1);
  std::vector<float> raw = positions(rows, *cfg.grid, nn::kRawInputs, 2);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 3; c < nn::kRawInputs; ++c) raw[r * nn::kRawInputs + c] = u(rng);
  cl::Buffer<float> draw(ctx(), std::span<const float>(raw));
  const std::size_t row0 = 5, n = rows - row0;  // encode a row range, as chunked inference does
  auto out_host = with_canaries(n * D);
  cl::Buffer<float> out(ctx(), std::span<const float>(out_host));
  enc.forward(draw, row0, n, out);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, n * D));
  const auto table = enc.grid()->params().read();
  const std::vector<double> tabled(table.begin(), table.end());
  for (std::size_t i = 0; i < n; ++i) {
    const float* row = &raw[(row0 + i) * nn::kRawInputs];
    std::vector<double> want = grid_encode(*cfg.grid, enc.grid()->levels(), tabled, row + nn::raw::kPosition);
    for (std::size_t src : {nn::raw::kDirection, nn::raw::kNormal}) {
      const auto s = sh16(row[src], row[src + 1], row[src + 2]);
      want.insert(want.end(), s.begin(), s.end());
    }
    for (std::size_t c = 0; c < 3; ++c) want.push_back(row[nn::raw::kAlbedo + c]);
    want.push_back(row[nn::raw::kRoughness]);
    // The grid features are ~1e-4 here; compare them tighter than the table's absolute floor.
    EXPECT_TRUE(all_near(std::span<const float>(&out_host[i * D], D), std::span<const double>(want),
                         Tolerance{kFloatKernel.rel, 1e-7}))
        << "row " << i;
  }
}

}  // namespace
}  // namespace clr::test
