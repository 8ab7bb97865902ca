// The composed network (encoder + MLP) end to end: gradients by finite differences of the double twins,
// checkpoint round trip and damage, and a fitting test on a known 3-D RGB field.
#include "nn/network.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/error.hpp"
#include "nn/checkpoint.hpp"
#include "nn/encoding_twin.hpp"
#include "nn/loss.hpp"
#include "nn/mlp_twin.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

nn::NetworkConfig small_network() {
  nn::NetworkConfig c;
  nn::HashGridConfig g;
  g.levels = 3;
  g.features = 2;
  g.log2_table = 7;
  g.base_resolution = 2;
  g.growth = 2.0;
  g.bbox_lo = {0.0f, -1.0f, 0.0f};
  g.bbox_hi = {2.0f, 1.0f, 1.0f};
  c.encoder.grid = g;
  c.encoder.sh_direction = true;
  c.encoder.sh_normal = false;
  c.encoder.albedo = true;
  c.width = 12;
  c.hidden_layers = 2;
  c.outputs = 3;
  c.output_activation = nn::OutputActivation::Abs;
  c.gemm = nn::GemmChoice::Own;
  c.seed = 5;
  return c;
}

std::vector<float> raw_rows(std::size_t rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> raw(rows * nn::kRawInputs);
  for (std::size_t r = 0; r < rows; ++r) {
    float* row = &raw[r * nn::kRawInputs];
    row[0] = 1.0f + u(rng);
    row[1] = u(rng);
    row[2] = 0.5f + 0.5f * u(rng);
    for (std::size_t s : {nn::raw::kDirection, nn::raw::kNormal}) {
      float v[3] = {u(rng), u(rng), u(rng) + 2.0f};
      const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int i = 0; i < 3; ++i) row[s + i] = v[i] / n;
    }
    for (int i = 0; i < 3; ++i) row[nn::raw::kAlbedo + i] = 0.5f + 0.4f * u(rng);
    row[nn::raw::kRoughness] = 0.5f;
  }
  return raw;
}

// A batch longer than one chunk (the residual metric's usual case: P·S rows in 262144-row pieces) is inferred chunk by
// chunk into its own rows of the output: bit-identical to the same network inferring it in one piece.
TEST_F(ClTest, ChunkedInferenceMatchesOnePiece) {
  const std::size_t rows = 30;
  auto chunked_cfg = small_network();
  chunked_cfg.max_chunk_rows = 7;
  nn::Network whole(ctx(), small_network()), chunked(ctx(), chunked_cfg);
  const auto raw = raw_rows(rows, 9);
  cl::Buffer<float> in(ctx(), std::span<const float>(raw));
  auto out_host = with_canaries(rows * 3, -1.0f);
  cl::Buffer<float> a(ctx(), std::span<const float>(out_host)), b(ctx(), std::span<const float>(out_host));
  whole.infer(in, rows, a);
  chunked.infer(in, rows, b);
  const auto va = a.read(), vb = b.read();
  EXPECT_EQ(va, vb);
  EXPECT_TRUE(canaries_intact(vb, rows * 3));
}

// With albedo_factor the outputs are the unfactored network's times max(albedo, floor), in training and in (chunked)
// inference, and the parameter gradients of a loss are the unfactored network's for d_output times that factor.
TEST_F(ClTest, AlbedoFactorMultipliesOutputsAndGradients) {
  const std::size_t rows = 40;
  auto plain_cfg = small_network();
  auto factored_cfg = plain_cfg;
  factored_cfg.albedo_factor = true;
  factored_cfg.max_chunk_rows = 9;  // inference in pieces: each piece must meet its own rows' albedo
  nn::Network plain(ctx(), plain_cfg), factored(ctx(), factored_cfg);
  auto raw = raw_rows(rows, 11);
  raw[3 * nn::kRawInputs + nn::raw::kAlbedo + 1] = 0.0f;  // a black channel: the floor applies
  std::vector<double> factor(rows * 3);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < 3; ++c)
      factor[r * 3 + c] = std::max(raw[r * nn::kRawInputs + nn::raw::kAlbedo + c], nn::kAlbedoFloor);
  cl::Buffer<float> in(ctx(), std::span<const float>(raw));
  nn::NetworkContext cp, cf;
  plain.forward_train(in, rows, cp);
  factored.forward_train(in, rows, cf);
  const auto yp = cp.output().read(), yf = cf.output().read();
  std::vector<double> want(rows * 3);
  for (std::size_t i = 0; i < want.size(); ++i) want[i] = yp[i] * factor[i];
  EXPECT_TRUE(all_near(std::span<const float>(yf.data(), want.size()), std::span<const double>(want)));
  cl::Buffer<float> out(ctx(), rows * 3);
  factored.infer(in, rows, out);
  EXPECT_TRUE(all_near(std::span<const float>(out.read()), std::span<const double>(want)));

  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> d(rows * 3), d_scaled(rows * 3);
  for (std::size_t i = 0; i < d.size(); ++i) {
    d[i] = u(rng);
    d_scaled[i] = float(d[i] * factor[i]);
  }
  cl::Buffer<float> dd(ctx(), std::span<const float>(d)), dds(ctx(), std::span<const float>(d_scaled));
  factored.backward(cf, dd);
  plain.backward(cp, dds);
  EXPECT_TRUE(all_near(std::span<const float>(factored.mlp().grads().read()),
                       std::span<const float>(plain.mlp().grads().read())));
  EXPECT_TRUE(all_near(std::span<const float>(factored.encoder().grid()->gradient()),
                       std::span<const float>(plain.encoder().grid()->gradient())));
  EXPECT_EQ(dd.read(), d) << "backward leaves the caller's d_output as it was";

  auto wide = plain_cfg;
  wide.outputs = 4;
  wide.albedo_factor = true;
  EXPECT_THROW(nn::Network(ctx(), wide), InputError) << "the factor is RGB: 3 outputs";
}

TEST_F(ClTest, NetworkGradientsMatchFiniteDifferences) {
  const auto cfg = small_network();
  nn::Network net(ctx(), cfg);
  auto* grid = net.encoder().grid();
  // Table values of order 1 (not the initialiser's 1e-4) so grid features matter to the output.
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> table(grid->params().size());
  for (auto& v : table) v = u(rng);
  grid->params().write(table);
  const std::size_t rows = 24, O = 3;
  const auto raw = raw_rows(rows, 3);
  std::vector<float> w(rows * O);
  for (auto& v : w) v = u(rng);
  cl::Buffer<float> draw(ctx(), std::span<const float>(raw)), dw(ctx(), std::span<const float>(w));
  nn::NetworkContext c;
  net.forward_train(draw, rows, c);
  net.backward(c, dw);
  const auto g_mlp = net.mlp().grads().read();
  const auto g_grid = grid->gradient();
  const auto p = net.mlp().params().read();

  MlpTwin mlp{net.mlp().config(), std::vector<double>(p.begin(), p.end())};
  const std::vector<double> tabled(table.begin(), table.end());
  auto loss = [&](const MlpTwin& m, const std::vector<double>& t) {
    double L = 0;
    for (std::size_t r = 0; r < rows; ++r) {
      const float* row = &raw[r * nn::kRawInputs];
      auto x = grid_encode(*cfg.encoder.grid, grid->levels(), t, row);
      const auto s = sh16(row[3], row[4], row[5]);
      x.insert(x.end(), s.begin(), s.end());
      for (int i = 0; i < 3; ++i) x.push_back(row[nn::raw::kAlbedo + i]);
      const auto out = m.forward_row(x.data());
      for (std::size_t j = 0; j < O; ++j) L += double(w[r * O + j]) * out[j];
    }
    return L;
  };
  const double h = 1e-6;
  for (std::size_t i = 0; i < mlp.p.size(); ++i) {
    MlpTwin a = mlp, b = mlp;
    a.p[i] += h;
    b.p[i] -= h;
    ASSERT_TRUE(near(g_mlp[i], (loss(a, tabled) - loss(b, tabled)) / (2 * h))) << "d/dmlp " << i;
  }
  for (std::size_t i = 0; i < tabled.size(); ++i) {
    auto a = tabled, b = tabled;
    a[i] += h;
    b[i] -= h;
    ASSERT_TRUE(near(g_grid[i], (loss(mlp, a) - loss(mlp, b)) / (2 * h))) << "d/dtable " << i;
  }
}

class CheckpointTest : public ClTest {
 protected:
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("clr_ckpt_" + std::to_string(::getpid()));
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string path(const std::string& name) {
    std::filesystem::create_directories(dir);
    return (dir / name).string();
  }
  // One training step on a fixed batch with the relative L2 loss against a fixed target.
  void step(nn::Network& net, const cl::Buffer<float>& raw, const cl::Buffer<float>& target, std::size_t rows,
            nn::NetworkContext& c, cl::Buffer<float>& grad) {
    nn::Loss loss(ctx());
    net.forward_train(raw, rows, c);
    loss.evaluate(c.output(), target, rows * 3, 1.0f / float(rows * 3), 1.0f, grad);
    net.backward(c, grad);
    net.adam_step();
  }
};

TEST_F(CheckpointTest, RoundTripReproducesTheNextStep) {
  const auto cfg = small_network();
  const std::size_t rows = 256;
  const auto raw = raw_rows(rows, 9);
  std::vector<float> target(rows * 3);
  for (std::size_t i = 0; i < target.size(); ++i) target[i] = 0.2f + 0.1f * float(i % 7);
  cl::Buffer<float> draw(ctx(), std::span<const float>(raw)), dt(ctx(), std::span<const float>(target)),
      grad(ctx(), rows * 3);
  nn::Network a(ctx(), cfg);
  nn::NetworkContext ca, cb;
  for (int i = 0; i < 3; ++i) step(a, draw, dt, rows, ca, grad);
  const auto file = path("model.clr");
  a.save(file, "rng-state-bytes\x01\x02");
  auto cfg_b = cfg;
  cfg_b.seed = 77;  // different initial parameters: load must overwrite every one of them
  nn::Network b(ctx(), cfg_b);
  EXPECT_EQ(b.load(file), "rng-state-bytes\x01\x02");
  EXPECT_EQ(b.steps(), 3u);
  EXPECT_EQ(b.mlp().params().read(), a.mlp().params().read());
  EXPECT_EQ(b.encoder().grid()->params().read(), a.encoder().grid()->params().read());
  step(a, draw, dt, rows, ca, grad);
  step(b, draw, dt, rows, cb, grad);
  // No float atomics in the step (ordered bias-gradient and split-K reductions, fixed-point hash-grid gradient):
  // the next step is the same bit for bit.
  EXPECT_EQ(b.mlp().params().read(), a.mlp().params().read());
  const auto ga = a.encoder().grid()->params().read(), gb = b.encoder().grid()->params().read();
  if (a.encoder().grid()->fixed_point_gradient()) {
    EXPECT_EQ(gb, ga);
  } else {
    // A device without int64 atomics accumulates the grid gradient with float CAS loops, whose order depends on
    // thread scheduling (docs/design.md §5): equal up to the last bits.
    EXPECT_TRUE(all_near(std::span<const float>(gb), std::span<const float>(ga), Tolerance{1e-5, 1e-9}));
  }
  // A config that differs in what the network computes is refused, naming the file.
  auto other = cfg;
  other.width = 16;
  nn::Network c(ctx(), other);
  try {
    c.load(file);
    FAIL() << "a checkpoint of another width was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("width"), std::string::npos) << e.what();
  }
}

// The weight average against a double twin over a few Adam steps; it travels in a checkpoint beside the
// parameters, and swap_average / adopt_average put it in their place.
TEST_F(CheckpointTest, WeightAverageFollowsItsTwinAndTravelsInTheCheckpoint) {
  const auto cfg = small_network();
  const std::size_t rows = 64;
  const auto raw = raw_rows(rows, 3);
  std::vector<float> target(rows * 3, 0.3f);
  cl::Buffer<float> draw(ctx(), std::span<const float>(raw)), dt(ctx(), std::span<const float>(target)),
      grad(ctx(), rows * 3);
  nn::Network net(ctx(), cfg);
  EXPECT_FALSE(net.averaging());
  EXPECT_FALSE(net.checkpoint().has("mlp.average"));
  net.start_average();
  ASSERT_TRUE(net.averaging());
  const auto params = [&] {
    auto p = net.mlp().params().read();
    const auto t = net.encoder().grid()->params().read();
    p.insert(p.end(), t.begin(), t.end());
    return p;
  };
  const auto p0 = params();
  std::vector<double> twin(p0.begin(), p0.end());
  nn::NetworkContext c;
  for (const float d : {0.5f, 0.9f, 0.99f}) {
    step(net, draw, dt, rows, c, grad);
    net.update_average(d);
    const auto p = params();
    for (std::size_t i = 0; i < twin.size(); ++i) twin[i] = d * twin[i] + (1.0 - d) * p[i];
  }
  const auto live = params();
  net.swap_average();
  EXPECT_TRUE(all_near(std::span<const float>(params()), std::span<const double>(twin)));
  EXPECT_NE(params(), live) << "the average is not the parameters";
  net.swap_average();
  EXPECT_EQ(params(), live) << "swapping twice restores the parameters";

  const auto file = path("averaged.clr");
  net.save(file);
  nn::Network resumed(ctx(), cfg);
  resumed.load(file);
  ASSERT_TRUE(resumed.averaging()) << "a checkpoint with an average resumes averaging";
  EXPECT_EQ(resumed.mlp().params().read(), net.mlp().params().read());
  resumed.adopt_average();
  EXPECT_FALSE(resumed.averaging());
  net.swap_average();
  EXPECT_EQ(resumed.mlp().params().read(), net.mlp().params().read()) << "the adopted parameters are the average";
  EXPECT_EQ(resumed.encoder().grid()->params().read(), net.encoder().grid()->params().read());
}

TEST_F(CheckpointTest, DamagedFilesAreInputErrors) {
  nn::Network net(ctx(), small_network());
  const auto file = path("good.clr");
  net.save(file);
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto write = [&](const std::string& name, const std::string& data) {
    const auto p = path(name);
    std::ofstream(p, std::ios::binary).write(data.data(), std::streamsize(data.size()));
    return p;
  };
  auto expect_error = [&](const std::string& p, const std::string& words) {
    try {
      net.load(p);
      ADD_FAILURE() << p << " loaded";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(p), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  };
  auto flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expect_error(write("flipped.clr", flipped), "checksum");
  expect_error(write("truncated.clr", bytes.substr(0, bytes.size() - 100)), "truncated");
  expect_error(write("short.clr", bytes.substr(0, 20)), "truncated header");
  auto magic = bytes;
  magic[0] = 'X';
  expect_error(write("magic.clr", magic), "magic");
  auto version = bytes;
  version[8] = 9;
  expect_error(write("version.clr", version), "version");
  expect_error(path("missing.clr"), "not found");
  // A valid file is still accepted after all that, and no temporary file is left behind by save.
  EXPECT_NO_THROW(net.load(file));
  EXPECT_FALSE(std::filesystem::exists(file + ".tmp"));
}

// Hash grid + MLP learn f(x) = RGB of three smooth functions over the unit cube. Requirement, fixed before
// running: after 600 steps of 1024 random points, the MSE on 4096 fresh points is below 2 % of the field's
// variance (an untrained network sits at ≈100 %, a constant predictor at exactly 100 %).
TEST_F(ClTest, HashGridMlpFitsAKnownField) {
  nn::NetworkConfig cfg;
  nn::HashGridConfig g;
  g.levels = 8;
  g.features = 2;
  g.log2_table = 14;
  g.base_resolution = 4;
  g.growth = 1.5;
  cfg.encoder.grid = g;
  cfg.encoder.sh_direction = cfg.encoder.sh_normal = cfg.encoder.albedo = false;
  cfg.width = 32;
  cfg.hidden_layers = 2;
  cfg.outputs = 3;
  cfg.adam.learning_rate = 1e-2f;
  cfg.gemm = nn::GemmChoice::Own;
  nn::Network net(ctx(), cfg);
  const double pi = 3.14159265358979323846;
  auto field = [&](const float* x, std::size_t ch) {
    switch (ch) {
      case 0:
        return 0.5 + 0.4 * std::sin(2 * pi * x[0]) * std::cos(pi * x[1]);
      case 1:
        return 0.5 + 0.4 * std::sin(3 * pi * (x[0] + x[2]) / 2);
      default:
        return 0.2 + 0.6 * x[1] * x[1] * (1 - x[2]);
    }
  };
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto batch = [&](std::size_t rows, std::vector<float>& raw, std::vector<float>& target) {
    raw.assign(rows * nn::kRawInputs, 0.0f);
    target.resize(rows * 3);
    for (std::size_t r = 0; r < rows; ++r) {
      for (int i = 0; i < 3; ++i) raw[r * nn::kRawInputs + i] = u(rng);
      for (std::size_t ch = 0; ch < 3; ++ch) target[r * 3 + ch] = float(field(&raw[r * nn::kRawInputs], ch));
    }
  };
  const std::size_t B = 1024;
  std::vector<float> raw, target;
  cl::Buffer<float> draw(ctx(), B * nn::kRawInputs), dt(ctx(), B * 3), grad(ctx(), B * 3);
  nn::Loss loss(ctx());
  nn::NetworkContext c;
  for (int s = 0; s < 600; ++s) {
    batch(B, raw, target);
    draw.write(raw);
    dt.write(target);
    net.forward_train(draw, B, c);
    loss.evaluate(c.output(), dt, B * 3, 1.0f / float(B * 3), 0.0f, grad);
    net.backward(c, grad);
    net.adam_step();
  }
  const std::size_t T = 4096;
  batch(T, raw, target);
  cl::Buffer<float> traw(ctx(), std::span<const float>(raw)), out(ctx(), T * 3);
  net.infer(traw, T, out);
  const auto pred = out.read();
  double mse = 0, mean = 0, var = 0;
  for (float t : target) mean += t;
  mean /= double(target.size());
  for (std::size_t i = 0; i < target.size(); ++i) {
    mse += (double(pred[i]) - target[i]) * (double(pred[i]) - target[i]);
    var += (target[i] - mean) * (target[i] - mean);
  }
  EXPECT_LT(mse / var, 0.02) << "MSE " << mse / double(target.size()) << ", variance " << var / double(target.size());
  EXPECT_EQ(loss.take().non_finite, 0u);
}

}  // namespace
}  // namespace clr::test
