// The runaway on the whole Veach Ajar (docs/method.md, "A ceiling on the power"), through the CLI as a user trains
// it (NR, CPU defaults, seed 1), judged by log.csv's `mean_ratio` against TungstenRender.exr box-downsampled to
// 160 × 90. The scene door-gap.xml imitates does not run away at any power; this one does, so the control case
// proves the measurement can fail: the relative residual held at power 1 over-brightens the image 14.8× by step 150
// (measured). The default schedule, its power capped at 0.5, stays within 0.83–1.39× from a fifth of a 1500-step
// budget on (seeds 1 and 2, measured every 75 steps); the bound asserted is [2/3, 3/2], a runaway's bound, not
// issue 46's ±30 %, which the high learning rate's swings on this scene still break (docs/method.md).
// About 6 minutes on 2 cores; skips where the shared scenes are absent.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "image/image.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"
#include "support/shared_scenes.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

class AjarRunaway : public CliRunDir {
 protected:
  AjarRunaway() : CliRunDir("ajar_runaway") {}

  void SetUp() override {
    CliRunDir::SetUp();
    if (IsSkipped()) return;
    CLR_REQUIRE_SHARED(shared_scenes() / "veach-ajar" / "TungstenRender.exr");
    const auto tungsten = image::read_exr(shared_scenes() / "veach-ajar" / "TungstenRender.exr");
    reference = (dir / "reference.exr").string();
    image::write_exr(reference, image::box_downsample(tungsten, tungsten.width / 160));
  }

  // The mean ratios logged at each evaluation of a run of `steps` NR steps, evaluated every `every` steps, trained
  // with the settings `settings_json` over the CPU defaults.
  std::vector<std::pair<long, double>> mean_ratios(long steps, long every, const std::string& settings_json) {
    const fs::path settings = dir / "settings.json", run = dir / ("run" + std::to_string(steps));
    std::ofstream(settings) << settings_json;
    const auto r =
        run_cli("train " + (shared_scenes() / "veach-ajar" / "scene.xml").string() + " --method nr --seed 1 --steps " +
                std::to_string(steps) + " --eval-every " + std::to_string(every) + " --reference " + reference +
                " --config " + settings.string() + " -q -o " + run.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::ifstream log(run / "log.csv");
    std::string line;
    std::getline(log, line);
    EXPECT_TRUE(line.size() > 11 && line.substr(line.size() - 11) == ",mean_ratio") << line;
    std::vector<std::pair<long, double>> ratios;
    while (std::getline(log, line)) {
      const auto comma = line.rfind(',');
      if (comma == std::string::npos || comma + 1 == line.size()) continue;
      ratios.emplace_back(std::stol(line), std::stod(line.substr(comma + 1)));
    }
    std::cout << "image mean / Tungsten's at steps";
    for (const auto& [step, ratio] : ratios) std::cout << " " << step << ": " << ratio;
    std::cout << "\n";
    return ratios;
  }

  std::string reference;
};

TEST_F(AjarRunaway, RelativeResidualHeldAtPowerOneRunsAway) {
  const auto ratios = mean_ratios(600, 50, R"({"relative_fade_end": 0, "relative_power_max": 1})");
  ASSERT_GE(ratios.size(), 12u);
  double worst = 0;
  for (const auto& [step, ratio] : ratios) worst = std::max(worst, ratio);
  EXPECT_GT(worst, 3.0) << "the control did not run away: the measurement cannot tell a runaway";
}

TEST_F(AjarRunaway, TheDefaultScheduleDoesNot) {
  const long steps = 1500;
  const auto ratios = mean_ratios(steps, 150, "{}");
  ASSERT_GE(ratios.size(), 10u);
  for (const auto& [step, ratio] : ratios) {
    if (step < steps / 5) continue;
    EXPECT_GT(ratio, 2.0 / 3.0) << "step " << step;
    EXPECT_LT(ratio, 1.5) << "step " << step;
  }
}

}  // namespace
}  // namespace clr::test
