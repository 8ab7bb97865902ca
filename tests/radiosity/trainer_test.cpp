// Neural Radiosity training end to end on small networks: analytic convergence, error that falls with steps,
// resume, and the run directory's rules. The paper's 4×512 network is exercised by the slow tests and benchmarks.
#include "radiosity/trainer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/error.hpp"
#include "nn/checkpoint.hpp"
#include "radiosity/residual.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"
#include "support/small_training.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
const fs::path kScenes = fs::path(CLR_SOURCE_DIR) / "scenes";

class TempRun {
 public:
  explicit TempRun(const std::string& name)
      : path(fs::temp_directory_path() / ("clr_" + name + std::to_string(::getpid()))) {
    fs::remove_all(path);
  }
  ~TempRun() { fs::remove_all(path); }
  fs::path path;
};

std::vector<std::vector<double>> read_log(const fs::path& run) {
  std::ifstream in(run / "log.csv");
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream s(line);
    // Cells left empty (the evaluation columns of a row without an evaluation) read as NaN.
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(cell.empty() ? NAN : std::stod(cell));
    if (!line.empty() && line.back() == ',') row.push_back(NAN);
    rows.push_back(row);
  }
  return rows;
}

double image_mean(const image::Image& img) {
  double s = 0;
  for (float v : img.rgb) s += v;
  return s / double(img.rgb.size());
}

class Training : public ClTest {
 protected:
  void isnr_resume_is_bit_exact(int lag);
};

TEST_F(Training, FurnaceConvergesToTheAnalyticRadiance) {
  // Closed diffuse cube, albedo ρ = 0.5, emission 1 everywhere: scattered radiance ρ·Le/(1−ρ) = 1 on the inside,
  // so every pixel is Le + 1 = 2. NR's fixed point is exact here; what remains is optimisation error.
  const auto scene = scene::load_scene(kScenes / "furnace-enclosure.xml");
  const geometry::Geometry geometry(scene);
  TempRun run("furnace");
  radiosity::Trainer trainer(ctx(), geometry, small_config(800), run.path, false);
  trainer.run();
  radiosity::RenderSettings settings;
  settings.spp = 1;
  const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx(), trainer.network()), settings);
  // Measured after 800 steps over seeds 1–4: image mean within 0.2 %, worst pixel 5.8 % (at the cube's edges,
  // where grid cells straddle two faces). Bounds: 1 % on the mean, 10 % on every pixel. A model stuck at
  // the first bounce (scattered ρ·Le = 0.5, pixel 1.5) fails both by far.
  EXPECT_NEAR(image_mean(img), 2.0, 0.02);
  for (float v : img.rgb) ASSERT_NEAR(v, 2.0f, 0.2f);

  // The learning rate held for the first half of the budget and annealed to its final fraction at the end.
  const auto log = read_log(run.path);
  const double lr = trainer.network().config().adam.learning_rate, final_lr = lr * trainer.config().anneal_final;
  EXPECT_NEAR(log[log.size() / 2 - 1][5], lr, 1e-5 * lr);
  EXPECT_LT(log.back()[5], 1.1 * final_lr);
  EXPECT_GE(log.back()[5], final_lr);
}

TEST_F(Training, CornellBoxErrorAndResidualFallWithSteps) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "32"}});
  const geometry::Geometry geometry(scene);
  reference::RenderOptions ref_options;
  ref_options.spp = 256;
  const auto ref = reference::render(geometry, ref_options);
  TempRun run("cbox");
  radiosity::Trainer trainer(ctx(), geometry, small_config(0), run.path, false);
  radiosity::RenderSettings settings;
  settings.spp = 4;
  std::vector<double> mape, residual;
  for (long steps : {20, 120, 400}) {
    while (long(trainer.steps_done()) < steps) trainer.step();
    const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx(), trainer.network()), settings);
    mape.push_back(image::compare(img, ref).mape);
    residual.push_back(radiosity::measure_residual(ctx(), geometry, trainer.network(), 2048, 16, 5).mean);
  }
  RecordProperty("mape", ::testing::PrintToString(mape));
  RecordProperty("residual", ::testing::PrintToString(residual));
  EXPECT_LT(mape[1], mape[0]);
  EXPECT_LT(mape[2], mape[1]);
  EXPECT_LT(residual[2], residual[0]);

  // The means over each material's points partition the whole: weighted by their points they give the totals.
  const auto r = radiosity::measure_residual(ctx(), geometry, trainer.network(), 2048, 16, 5);
  ASSERT_EQ(r.by_material.size(), scene.materials.size());
  std::size_t points = 0, parts = 0;
  double mean = 0, variance = 0;
  for (const auto& part : r.by_material) {
    points += part.points;
    parts += part.points > 0;
    mean += double(part.points) * part.mean;
    variance += double(part.points) * part.rhs_variance;
  }
  EXPECT_EQ(points, r.points);
  EXPECT_GE(parts, 3u);  // the white walls, the red one and the green one at least
  EXPECT_NEAR(mean / double(points), r.mean, 1e-9 * r.mean);
  EXPECT_NEAR(variance / double(points), r.rhs_variance, 1e-9 * r.rhs_variance);
}

TEST_F(Training, ResumeContinuesTheLossCurve) {
  // The furnace: its target has no Monte Carlo noise, so the loss curve shows training progress clearly.
  const auto scene = scene::load_scene(kScenes / "furnace-enclosure.xml");
  const geometry::Geometry geometry(scene);
  const radiosity::RenderSettings settings{.width = 0, .height = 0, .spp = 1};
  TempRun run("resume");
  image::Image before;
  {
    // Annealing off: the first session would anneal to its own 100-step budget, and the comparison of the two
    // halves below is about the checkpoint carrying the state across, not about the learning rate.
    auto config = small_config(100);
    config.anneal_start = 1.0;
    radiosity::Trainer first(ctx(), geometry, config, run.path, false);
    first.run();
    before = radiosity::render(geometry, radiosity::radiance_query(ctx(), first.network()), settings);
  }
  auto config = small_config(200);
  config.network = nlohmann::json::object();  // ignored on resume: the run's own settings win
  radiosity::Trainer second(ctx(), geometry, config, run.path, true);
  EXPECT_EQ(second.steps_done(), 100u);
  EXPECT_EQ(second.config().network["width"], 128);
  // The checkpoint restores the network exactly: the same device renders the same image, bit for bit.
  const auto resumed = radiosity::render(geometry, radiosity::radiance_query(ctx(), second.network()), settings);
  EXPECT_EQ(resumed.rgb, before.rgb);
  second.run();
  EXPECT_EQ(second.steps_done(), 200u);

  const auto log = read_log(run.path);
  ASSERT_EQ(log.size(), 20u);
  for (std::size_t i = 0; i < log.size(); ++i) {
    EXPECT_EQ(log[i][0], double(10 * (i + 1))) << "steps continue without a gap or a repeat";
    if (i) {
      EXPECT_GE(log[i][1], log[i - 1][1]) << "time continues across the resume";
    }
  }
  // The resumed half continues at the level the first half reached (means of 5 rows smooth the batch noise)
  // and goes on falling.
  const auto mean = [&](std::size_t from, std::size_t n) {
    double s = 0;
    for (std::size_t i = from; i < from + n; ++i) s += log[i][2];
    return s / double(n);
  };
  EXPECT_LT(mean(10, 5), 1.2 * mean(5, 5));
  EXPECT_LT(mean(15, 5), mean(0, 3));
}

// ISNR's step is deterministic (fixed-point hash-grid gradients, per-point guide gradients), so a run stopped and
// resumed must end bit for bit where an uninterrupted run ends: both modules travel in model.clr.
// With the lagged guide the checkpoint also carries the I-Module before its last update, which the first resumed
// step draws from as the uninterrupted run did.
TEST_F(Training, IsnrResumeIsBitExact) {
  for (const int lag : {0, 1}) {
    SCOPED_TRACE("guide_lag " + std::to_string(lag));
    isnr_resume_is_bit_exact(lag);
  }
}

void Training::isnr_resume_is_bit_exact(int lag) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  const radiosity::RenderSettings settings{.width = 0, .height = 0, .spp = 1};
  auto config = small_config(40);
  config.guide_lag = lag;
  // Schedules that depend on the budget would differ between a 20-step and a 40-step session.
  config.anneal_start = 1.0;
  config.relative_fade_end = 0.0;
  config.guide_warmup = 0.0;
  ASSERT_EQ(config.method, radiosity::Method::Isnr);
  TempRun straight("isnr_straight" + std::to_string(lag)), halves("isnr_halves" + std::to_string(lag));
  radiosity::Trainer a(ctx(), geometry, config, straight.path, false);
  ASSERT_NE(a.guide(), nullptr);
  a.run();
  auto first = config;
  first.steps = 20;
  radiosity::Trainer(ctx(), geometry, first, halves.path, false).run();
  radiosity::Trainer b(ctx(), geometry, config, halves.path, true);
  ASSERT_NE(b.guide(), nullptr);
  EXPECT_EQ(b.guide()->steps(), 20u);
  b.run();
  EXPECT_EQ(b.guide()->mlp().params().read(), a.guide()->mlp().params().read());
  EXPECT_EQ(b.guide()->encoder().grid()->params().read(), a.guide()->encoder().grid()->params().read());
  EXPECT_EQ(radiosity::render(geometry, radiosity::radiance_query(ctx(), b.network()), settings).rgb,
            radiosity::render(geometry, radiosity::radiance_query(ctx(), a.network()), settings).rgb);
  // The log has the I-Module's columns, and its loss is finite.
  const auto log = read_log(halves.path);
  ASSERT_EQ(log.size(), 4u);
  for (const auto& row : log) {
    ASSERT_EQ(row.size(), 14u) << "the I-Module's two columns, the three (empty) evaluation columns, the samples "
                                  "seen, then the (empty) mean ratio";
    EXPECT_EQ(row[12], row[0] * double(b.config().batch) * double(b.config().samples));
    EXPECT_TRUE(std::isnan(row[9]) && std::isnan(row[13])) << "no evaluation without a reference";
    EXPECT_TRUE(std::isfinite(row[7]));
    EXPECT_NEAR(row[8], 1.0 - config.bsdf_fraction, 0.02) << "guided share";
  }
}

// With a weight average, evaluation sees the average (not the parameters), model.clr keeps both, a resumed run
// continues both bit for bit, and a model loaded to be rendered is the average.
TEST_F(Training, WeightAverageIsWhatIsEvaluatedResumedAndRendered) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  auto config = small_config(40);
  config.method = radiosity::Method::Nr;
  config.average_steps = 10;
  config.anneal_start = 1.0;  // schedules of the budget would differ between a 20- and a 40-step session
  config.relative_fade_end = 0.0;
  TempRun straight("avg_straight"), halves("avg_halves");
  radiosity::Trainer a(ctx(), geometry, config, straight.path, false);
  ASSERT_TRUE(a.network().averaging());
  std::vector<float> evaluated;
  radiosity::Trainer::RunOptions options;
  options.evaluate_every = 1000;  // the run's last step only
  options.evaluate = [&]() -> std::optional<image::Metrics> {
    evaluated = a.network().mlp().params().read();
    return std::nullopt;
  };
  a.run(options);
  const auto live = a.network().mlp().params().read();
  ASSERT_FALSE(evaluated.empty());
  EXPECT_NE(evaluated, live) << "the evaluation saw the average, not the parameters";
  const auto rendered = radiosity::RunDirectory::load_radiance(ctx(), straight.path);
  EXPECT_FALSE(rendered->averaging());
  EXPECT_EQ(rendered->mlp().params().read(), evaluated) << "the model rendered is the average evaluated";
  EXPECT_EQ(radiosity::RunDirectory::load_radiance(ctx(), straight.path, true)->mlp().params().read(), live);

  auto first = config;
  first.steps = 20;
  radiosity::Trainer(ctx(), geometry, first, halves.path, false).run();
  radiosity::Trainer b(ctx(), geometry, config, halves.path, true);
  ASSERT_TRUE(b.network().averaging());
  b.run();
  EXPECT_EQ(b.network().mlp().params().read(), live);
  EXPECT_EQ(radiosity::RunDirectory::load_radiance(ctx(), halves.path)->mlp().params().read(), evaluated)
      << "the resumed run's average is the uninterrupted run's";
}

// The pipelined step (step k+1's batch prepared on the host while the device runs step k) trains exactly what the
// serial step trains: NR (points and traced incident half ahead), ISNR with guided directions (points ahead) and
// ISNR with c = 1 throughout (both ahead). Each pipelined run must actually have used batches prepared ahead.
TEST_F(Training, PipelinedStepsMatchSerialBitForBit) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  struct Variant {
    const char* name;
    radiosity::Method method;
    double bsdf_fraction;
    int guide_lag = 0;
  };
  for (const Variant v :
       {Variant{"nr", radiosity::Method::Nr, 0.5}, Variant{"isnr", radiosity::Method::Isnr, 0.5},
        Variant{"isnr_c1", radiosity::Method::Isnr, 1.0}, Variant{"isnr_lag", radiosity::Method::Isnr, 0.5, 1}}) {
    SCOPED_TRACE(v.name);
    auto config = small_config(12);
    config.method = v.method;
    config.bsdf_fraction = v.bsdf_fraction;
    config.guide_lag = v.guide_lag;
    config.guide_warmup = 0.25;  // part of the run ramps c, part holds it
    TempRun serial_run(std::string("sched_serial_") + v.name), piped_run(std::string("sched_piped_") + v.name);
    radiosity::Trainer serial(ctx(), geometry, config, serial_run.path, false);
    radiosity::Trainer piped(ctx(), geometry, config, piped_run.path, false);
    serial.set_schedule(radiosity::StepSchedule::Serial);
    piped.set_schedule(radiosity::StepSchedule::Pipelined);
    serial.run();
    piped.run();
    EXPECT_EQ(serial.steps_prepared_ahead(), 0u);
    EXPECT_EQ(piped.steps_prepared_ahead(), 11u);  // with the lag: traced ahead too, through the warm-up's ramp
    ASSERT_EQ(piped.steps_done(), 12u);
    EXPECT_EQ(piped.network().mlp().params().read(), serial.network().mlp().params().read());
    EXPECT_EQ(piped.network().encoder().grid()->params().read(), serial.network().encoder().grid()->params().read());
    ASSERT_EQ(piped.guide() != nullptr, v.method == radiosity::Method::Isnr);
    if (piped.guide()) {
      EXPECT_EQ(piped.guide()->mlp().params().read(), serial.guide()->mlp().params().read());
      EXPECT_EQ(piped.guide()->encoder().grid()->params().read(), serial.guide()->encoder().grid()->params().read());
    }
    // The logs' batch columns agree (step, lookups, non-finite count, learning rate, residual power, guided share);
    // not the time, nor the losses, which are summed with float atomics in whatever order work-items run.
    const auto a = read_log(serial_run.path), b = read_log(piped_run.path);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t r = 0; r < a.size(); ++r)
      for (const std::size_t col : {0u, 3u, 4u, 5u, 6u, 8u})
        if (col < a[r].size() && !(std::isnan(a[r][col]) && std::isnan(b[r].at(col)))) {  // empty in both
          EXPECT_EQ(a[r][col], b[r].at(col)) << "log row " << r << " column " << col;
        }
  }
}

// The lagged guide draws step k+1's directions from the I-Module before step k's update: with guided directions it
// trains other parameters than the unlagged guide, and with none (c = 1 throughout: p̃ = p_bsdf, the lobes only
// learn) exactly the same ones. Its checkpoint carries the I-Module before the last update.
TEST_F(Training, LaggedGuideChangesOnlyTheGuidedDraw) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  for (const double c : {0.5, 1.0}) {
    SCOPED_TRACE("c = " + std::to_string(c));
    auto config = small_config(8);
    config.bsdf_fraction = c;
    config.guide_warmup = 0.0;
    TempRun fresh_run("lag0"), lagged_run("lag1");
    config.guide_lag = 0;
    radiosity::Trainer fresh(ctx(), geometry, config, fresh_run.path, false);
    config.guide_lag = 1;
    radiosity::Trainer lagged(ctx(), geometry, config, lagged_run.path, false);
    fresh.run();
    lagged.run();
    const bool same = lagged.network().mlp().params().read() == fresh.network().mlp().params().read();
    EXPECT_EQ(same, c == 1.0);
    EXPECT_EQ(lagged.guide()->mlp().params().read() == fresh.guide()->mlp().params().read(), c == 1.0);
    const auto has_before = [](const fs::path& run) {
      const auto ckpt = nn::read_checkpoint((run / "model.clr").string());
      return std::any_of(ckpt.tensors.begin(), ckpt.tensors.end(),
                         [](const auto& t) { return t.first == "guide_before.mlp.params"; });
    };
    EXPECT_TRUE(has_before(lagged_run.path));
    EXPECT_FALSE(has_before(fresh_run.path));
  }
}

// The lagged guide is the default for new runs; a run written before it existed (no guide_lag in config.json) goes
// on unlagged when resumed, as it was trained.
TEST_F(Training, RunsWithoutAGuideLagResumeUnlagged) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  TempRun run("no_lag_key");
  auto config = small_config(2);
  {
    radiosity::Trainer fresh(ctx(), geometry, config, run.path, false);
    EXPECT_EQ(fresh.config().guide_lag, 1);
    fresh.run();
  }
  nlohmann::json saved;
  std::ifstream(run.path / "config.json") >> saved;
  saved.erase("guide_lag");
  std::ofstream(run.path / "config.json") << saved.dump(2);
  config.steps = 3;
  radiosity::Trainer resumed(ctx(), geometry, config, run.path, true);
  EXPECT_EQ(resumed.config().guide_lag, 0);
  resumed.run();
  EXPECT_EQ(resumed.steps_done(), 3u);
}

// The trainer's GPU-typed choices — batch 16384, the 512-wide N-Module, the GEMM plans and launch shapes of a GPU —
// on a PoCL context that reports itself as an H200-sized GPU (132 compute units): NR and ISNR steps run, count no
// non-finite term and leave finite parameters. The first H200 run threw at its first step on a path only a GPU
// takes (docs/nvidia.md).
TEST_F(Training, GpuShapedDeviceTakesFiniteSteps) {
  cl::DeviceInfo gpu = ctx().device();
  gpu.type = cl::DeviceType::Gpu;
  gpu.compute_units = 132;
  cl::Context on(gpu);
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  for (const radiosity::Method method : {radiosity::Method::Nr, radiosity::Method::Isnr}) {
    SCOPED_TRACE(method == radiosity::Method::Nr ? "nr" : "isnr");
    radiosity::TrainConfig config;  // the device's defaults
    config.method = method;
    config.steps = 2;
    config.guide_warmup = 0.0;  // the guided branch from the first step
    TempRun run("gpu_shaped");
    radiosity::Trainer trainer(on, geometry, config, run.path, false);
    EXPECT_EQ(trainer.config().batch, 16384);
    std::uint32_t non_finite = 0;
    for (int i = 0; i < 2; ++i) non_finite += trainer.step().non_finite;
    EXPECT_EQ(non_finite, 0u);
    for (const float p : trainer.network().mlp().params().read()) ASSERT_TRUE(std::isfinite(p));
    if (trainer.guide()) {
      for (const float p : trainer.guide()->mlp().params().read()) ASSERT_TRUE(std::isfinite(p));
    }
  }
}

// A run directory written before ISNR existed has no `method` (nor the I-Module's keys) in its config.json: it
// resumes as the vanilla NR run it was.
TEST_F(Training, RunsWithoutAMethodResumeAsNr) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  TempRun run("old_nr");
  auto config = small_config(10);
  config.method = radiosity::Method::Nr;
  radiosity::Trainer(ctx(), geometry, config, run.path, false).run();
  std::ifstream in(run.path / "config.json");
  auto saved = nlohmann::json::parse(in);
  for (const char* key : {"method", "is_loss", "bsdf_fraction", "guide"}) saved.erase(key);
  std::ofstream(run.path / "config.json") << saved.dump(2);
  config.steps = 20;
  config.method = radiosity::Method::Isnr;  // only the stopping rule is taken from a resuming invocation
  radiosity::Trainer resumed(ctx(), geometry, config, run.path, true);
  EXPECT_EQ(resumed.config().method, radiosity::Method::Nr);
  EXPECT_EQ(resumed.guide(), nullptr);
  resumed.run();
  EXPECT_EQ(resumed.steps_done(), 20u);
}

// The sweep's use of a run: snapshots written from the step hook, whose time is not training time, and a time
// budget that counts every session of a resumed run.
TEST_F(Training, SnapshotsOnTheWayAndABudgetInTotal) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  const geometry::Geometry geometry(scene);
  TempRun run("snapshots");
  auto config = small_config(0);
  config.minutes = 0.01;  // 0.6 s
  const fs::path snapshot = run.path / "snapshot";
  double snapshot_seconds = 0;
  std::uint64_t snapshot_steps = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  {
    radiosity::Trainer trainer(ctx(), geometry, config, run.path / "train", false);
    radiosity::Trainer::RunOptions options;
    options.after_step = [&](double seconds) {
      if (snapshot_steps > 0 || seconds < 0.3) return;
      trainer.save_snapshot(snapshot);
      snapshot_seconds = seconds;
      snapshot_steps = trainer.steps_done();
      std::this_thread::sleep_for(std::chrono::milliseconds(800));  // as long as the whole budget: not counted
    };
    trainer.run(options);
    EXPECT_GE(trainer.seconds_trained(), 0.6);
    EXPECT_LT(trainer.seconds_trained(), 0.6 + 0.5);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  EXPECT_GT(wall, 0.6 + 0.8);
  ASSERT_GT(snapshot_steps, 0u) << "the hook never saw 0.3 s of training";
  EXPECT_GE(snapshot_seconds, 0.3);
  // A snapshot is a run directory of its own: its networks load as render and residual load them.
  EXPECT_EQ(radiosity::RunDirectory::load_radiance(ctx(), snapshot)->steps(), snapshot_steps);
  EXPECT_NE(radiosity::RunDirectory::load_guide(ctx(), snapshot), nullptr);

  // Resumed with a budget in total, a run past it takes no step; a larger total continues to it, not beyond.
  radiosity::Trainer::RunOptions in_total;
  in_total.minutes_in_total = true;
  std::uint64_t steps = 0;
  {  // a trainer holds its run directory's lock while it lives
    radiosity::Trainer spent(ctx(), geometry, config, run.path / "train", true);
    steps = spent.steps_done();
    spent.run(in_total);
    EXPECT_EQ(spent.steps_done(), steps);
  }
  config.minutes = 0.02;
  radiosity::Trainer more(ctx(), geometry, config, run.path / "train", true);
  const double before = more.seconds_trained();
  more.run(in_total);
  EXPECT_GT(more.steps_done(), steps);
  EXPECT_GE(more.seconds_trained(), 1.2);
  EXPECT_LT(more.seconds_trained() - before, 1.2 - 0.3) << "the second session counted its own budget";
}

TEST_F(Training, RunDirectoryRules) {
  const auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "32"}});
  const geometry::Geometry geometry(scene);
  TempRun run("rules");
  EXPECT_THROW(radiosity::Trainer(ctx(), geometry, small_config(1), run.path, true), InputError);
  fs::create_directories(run.path);
  std::ofstream(run.path / "stray.txt") << "x";
  try {
    radiosity::Trainer(ctx(), geometry, small_config(1), run.path, false);
    FAIL() << "trained into a non-empty directory";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("not empty"));
  }
}

}  // namespace
}  // namespace clr::test
