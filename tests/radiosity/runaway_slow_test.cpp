// No run may run away (docs/method.md, "The residual"): on scenes/door-gap.xml — Veach Ajar in miniature, a room lit
// only through a narrow gap by a light that few paths find — a model trained with the default settings keeps its
// image mean within ±30 % of the path tracer's at every evaluation from a tenth of its budget on, for NR, ISNR-KL and
// ISNR-IKL. The same test with the relative residual held near power 1 (the old default: fading to L2 only at the end
// of the budget) fails, which is what it guards against (printed by the last case, not asserted: it documents the
// failure the defaults avoid).
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/renderer.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

double mean(const image::Image& img) {
  double s = 0;
  for (float v : img.rgb) s += v;
  return s / double(img.rgb.size());
}

struct Case {
  const char* name;
  radiosity::Method method;
  radiosity::IsLoss is_loss;
  bool old_schedule;  // the relative residual fading to L2 over the whole budget, NEE off: expected to run away
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Runaway : public ClTest, public ::testing::WithParamInterface<Case> {
 protected:
  static const image::Image& reference(const geometry::Geometry& geometry) {
    // 1024 spp: the image mean to well under 1 %, which the ±30 % bound needs, whatever the pixel noise.
    static const image::Image ref = [&] {
      reference::RenderOptions opt;
      opt.spp = 1024;
      opt.seed = 11;
      return reference::render(geometry, opt);
    }();
    return ref;
  }
};

constexpr long kSteps = 600, kEvery = 60;

TEST_P(Runaway, ImageMeanStaysNearTheReference) {
  const Case c = GetParam();
  const auto scene = scene::load_scene(fs::path(CLR_SOURCE_DIR) / "scenes" / "door-gap.xml");
  const geometry::Geometry geometry(scene);
  const double want = mean(reference(geometry));
  ASSERT_GT(want, 0.0);

  radiosity::TrainConfig config;
  config.steps = kSteps;
  config.method = c.method;
  config.is_loss = c.is_loss;
  config.batch = 2048;
  config.log_every = 1000000;
  config.checkpoint_every = 1000000;
  if (c.old_schedule) {
    config.residual = radiosity::Residual::Relative;
    config.relative_fade_end = 1.0;
    config.nee = false;
  }
  const fs::path run = fs::temp_directory_path() / ("clr_runaway_" + std::to_string(::getpid()));
  fs::remove_all(run);
  radiosity::Trainer trainer(ctx(), geometry, config, run, false);
  std::vector<std::pair<long, double>> ratios;
  radiosity::Trainer::RunOptions options;
  options.evaluate_every = kEvery;
  options.evaluate = [&] {
    const radiosity::RenderSettings settings{.width = 48, .height = 48, .spp = 2};
    const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx(), trainer.network()), settings);
    ratios.emplace_back(long(trainer.steps_done()), mean(img) / want);
    return image::compare(img, reference(geometry));
  };
  trainer.run(options);
  fs::remove_all(run);

  std::cout << c.name << ": image mean / the path tracer's at steps";
  double worst = 1;
  for (const auto& [step, ratio] : ratios) {
    std::cout << " " << step << ": " << ratio;
    if (step >= kSteps / 10 && std::fabs(ratio - 1) > std::fabs(worst - 1)) worst = ratio;
  }
  std::cout << "\n";
  ASSERT_GE(ratios.size(), 9u);
  if (c.old_schedule) {
    std::cout << c.name << ": the old schedule's worst ratio " << worst << " (not asserted)\n";
    return;
  }
  EXPECT_GT(worst, 0.7) << c.name;
  EXPECT_LT(worst, 1.3) << c.name;
}

INSTANTIATE_TEST_SUITE_P(DoorGap, Runaway,
                         ::testing::Values(Case{"nr", radiosity::Method::Nr, radiosity::IsLoss::Ikl, false},
                                           Case{"isnr_kl", radiosity::Method::Isnr, radiosity::IsLoss::Kl, false},
                                           Case{"isnr_ikl", radiosity::Method::Isnr, radiosity::IsLoss::Ikl, false},
                                           Case{"nr_old_schedule", radiosity::Method::Nr, radiosity::IsLoss::Ikl,
                                                true}),
                         [](const auto& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace clr::test
