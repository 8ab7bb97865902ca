// Data-parallel training and distributed references across the ranks of `mpirun -np 2 clr_mpi_tests`
// (docs/mpi.md). Every test runs on every rank and calls the collectives in the same order; comparisons against rank 0
// are made on each rank, so a rank that differs fails there (and its non-zero exit fails the job).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "distributed/communicator.hpp"
#include "distributed/gradient_exchange.hpp"
#include "distributed/image_rows.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/trainer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"
#include "support/small_training.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using distributed::Communicator;
const fs::path kScenes = fs::path(CLR_SOURCE_DIR) / "scenes";

const Communicator& ranks() { return Communicator::world(); }

// One name on every rank (rank 0's pid) for a run rank 0 writes; removed by rank 0 when done.
class SharedRunDir {
 public:
  explicit SharedRunDir(const std::string& name) {
    std::uint64_t pid = std::uint64_t(::getpid());
    ranks().broadcast(std::span<std::uint64_t>(&pid, 1));
    path = fs::temp_directory_path() / ("clr_mpi_" + name + std::to_string(pid));
    if (ranks().rank() == 0) fs::remove_all(path);
    ranks().max(0);  // no rank starts before the directory is fresh
  }
  ~SharedRunDir() {
    ranks().max(0);
    if (ranks().rank() == 0) fs::remove_all(path);
  }
  fs::path path;
};

// Rank 0's copy of `values` (sizes agree on every rank).
std::vector<float> rank0s(std::vector<float> values) {
  ranks().broadcast(std::span<float>(values));
  return values;
}

bool bit_identical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

class DataParallel : public ClTest {
 protected:
  void SetUp() override {
    ClTest::SetUp();
    if (IsSkipped()) return;
    ASSERT_EQ(ranks().size(), 2) << "run under mpirun -np 2";
  }
};

TEST_F(DataParallel, RanksHoldIdenticalParametersAfter50Steps) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  const SharedRunDir run("same");
  radiosity::Trainer trainer(ctx(), geometry, small_config(50), run.path, false, ranks());
  ASSERT_NE(trainer.guide(), nullptr);  // isnr: both modules exchange
  trainer.run();
  EXPECT_EQ(trainer.steps_done(), 50u);
  for (nn::Network* net : {&trainer.network(), trainer.guide()}) {
    const auto mlp = net->mlp().params().read(), table = net->encoder().grid()->params().read();
    EXPECT_TRUE(bit_identical(mlp, rank0s(mlp))) << "rank " << ranks().rank() << ": MLP parameters";
    EXPECT_TRUE(bit_identical(table, rank0s(table))) << "rank " << ranks().rank() << ": hash table";
  }
  // Each rank trained its half of every batch: one took points the other did not.
  EXPECT_GT(trainer.exchange().stats().exchanges, 0u);
}

TEST_F(DataParallel, TwoRanksEqualOneRankWithTheSameGlobalBatch) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  const SharedRunDir run("pair");
  const fs::path alone = run.path.string() + "_alone" + std::to_string(ranks().rank());
  fs::remove_all(alone);
  radiosity::Trainer both(ctx(), geometry, small_config(1), run.path, false, ranks());
  radiosity::Trainer one(ctx(), geometry, small_config(1), alone, false, Communicator::single());
  both.step();
  one.step();
  for (auto [a, b] : {std::pair{&both.network(), &one.network()}, std::pair{both.guide(), one.guide()}}) {
    // The table's fixed-point gradient sums exactly in any order, so one step moves it identically.
    const nn::HashGrid& ga = *a->encoder().grid();
    if (ga.fixed_point_gradient()) {
      EXPECT_TRUE(bit_identical(ga.params().read(), b->encoder().grid()->params().read()));
    }
    // The MLP's gradient sums the batch's rows in another order: equal within float rounding. Adam's first
    // moment after one step is (1 − β1)·gradient, so it compares the summed gradients themselves; the parameters
    // moved by at most lr (5e-3), and rounding may shift a step by a small fraction of that.
    const nn::Checkpoint ca = a->checkpoint(), cb = b->checkpoint();
    for (const char* name : {"mlp.adam.m", "mlp.params"}) {
      const auto& ta = ca.tensor("2 ranks", name, a->mlp().params().size());
      const auto& tb = cb.tensor("1 rank", name, b->mlp().params().size());
      double largest = 0;
      for (float v : tb) largest = std::max(largest, double(std::abs(v)));
      const double tolerance = std::string(name) == "mlp.params" ? 5e-5 : 1e-3 * largest;
      std::size_t far = 0;
      double worst = 0;
      for (std::size_t i = 0; i < ta.size(); ++i) {
        const double diff = std::abs(double(ta[i]) - double(tb[i]));
        worst = std::max(worst, diff);
        if (diff > tolerance) ++far;
      }
      EXPECT_EQ(far, 0u) << name << ": largest difference " << worst << " (tolerance " << tolerance << ")";
      if (std::string(name) == "mlp.adam.m") {
        EXPECT_GT(largest, 0.0) << "no gradient reached the MLP";
      }
    }
  }
  fs::remove_all(alone);
}

TEST_F(DataParallel, SparseExchangeSumsTheDenseGradients) {
  // Two ranks back-propagate different rows; after the exchange both hold the dense sum of their table gradients
  // and the union of the entries they touched — including entries only the other rank reached.
  nn::NetworkConfig config = nn::n_module_config({0, 0, 0}, {1, 1, 1});
  config.width = 32;
  config.hidden_layers = 1;
  // Cells fine enough (16 across, growing 1.5×) that 64 rows a rank touch a small part of the table, each rank its
  // own entries: the exchange is sparse, and the other rank's entries can be seen arriving.
  config.encoder.grid->levels = 4;
  config.encoder.grid->log2_table = 12;
  config.encoder.grid->base_resolution = 16;
  config.encoder.grid->growth = 1.5;
  nn::Network net(ctx(), config);
  const std::size_t rows = 64;
  std::mt19937 rng(unsigned(17 + ranks().rank()));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> raw(rows * nn::kRawInputs), d(rows * 3);
  for (auto& v : raw) v = u(rng);
  for (auto& v : d) v = u(rng) - 0.5f;
  cl::Buffer<float> draw(ctx(), std::span<const float>(raw)), dd(ctx(), std::span<const float>(d));
  nn::NetworkContext c;
  net.forward_train(draw, rows, c);
  net.backward(c, dd);

  nn::HashGrid& grid = *net.encoder().grid();
  std::vector<double> want(grid.params().size());
  const auto mine = grid.gradient();
  std::copy(mine.begin(), mine.end(), want.begin());
  ranks().sum(want);
  const auto touched = grid.touched().read();
  std::vector<float> want_mlp = net.mlp().grads().read();
  ranks().sum(want_mlp);

  distributed::GradientExchange exchange(ctx(), ranks());
  exchange.reduce(net);
  const auto got = grid.gradient();
  const auto got_touched = grid.touched().read();
  std::size_t wrong = 0, only_others = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    if (std::abs(double(got[i]) - want[i]) > 1e-6 * std::abs(want[i]) + 1e-12) ++wrong;
  for (std::size_t e = 0; e < got_touched.size(); ++e) {
    if (touched[e] && !got_touched[e]) ++wrong;
    if (!touched[e] && got_touched[e]) ++only_others;
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(only_others, 0u) << "the other rank's rows never arrived";
  EXPECT_TRUE(bit_identical(net.mlp().grads().read(), want_mlp));
  EXPECT_LT(exchange.stats().bytes, exchange.stats().dense_bytes);
}

TEST_F(DataParallel, DivergedParametersStopTheRun) {
  nn::NetworkConfig config = radiosity::i_module_config({0, 0, 0}, {1, 1, 1});
  nn::Network net(ctx(), config);
  const distributed::GradientExchange exchange(ctx(), ranks());
  EXPECT_NO_THROW(exchange.check_same_parameters(net, "I-Module", 1));
  if (ranks().rank() == 1) {
    auto p = net.mlp().params().read();
    p[7] += 1e-3f;
    net.mlp().params().write(p);
  }
  if (ranks().rank() == 1)
    EXPECT_THROW(exchange.check_same_parameters(net, "I-Module", 2), std::runtime_error);
  else
    EXPECT_NO_THROW(exchange.check_same_parameters(net, "I-Module", 2));
}

TEST(DistributedReference, ImageEqualsTheSingleProcessOne) {
  ASSERT_EQ(ranks().size(), 2);
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml");
  const geometry::Geometry geometry(scene);
  reference::RenderOptions options;
  options.width = 24;
  options.height = 19;  // odd: the ranks' shares differ by a row
  options.spp = 4;
  options.seed = 3;
  const auto whole = reference::render(geometry, options);
  options.row_offset = ranks().rank();
  options.row_stride = ranks().size();
  const auto shared = distributed::gather_interleaved_rows(ranks(), reference::render(geometry, options));
  if (ranks().rank() == 0) {
    EXPECT_EQ(shared.width, whole.width);
    EXPECT_EQ(shared.height, whole.height);
    EXPECT_TRUE(bit_identical(shared.rgb, whole.rgb));
  } else {
    EXPECT_TRUE(shared.rgb.empty());
  }
}

}  // namespace
}  // namespace clr::test
