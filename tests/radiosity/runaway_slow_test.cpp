// No run may run away (docs/method.md, "The relative residual, fading to L2, and a dark start"): on
// scenes/door-gap.xml — Veach Ajar in miniature, a room lit only through a narrow gap by a light that few paths find —
// a model trained with the default settings keeps its image mean within ±30 % of the path tracer's at every evaluation
// from a fifth of its budget on, for NR, ISNR-KL and ISNR-IKL (slow: about 6 minutes on 2 cores). The first
// evaluation, at a tenth, is printed but not judged: it measured 1.02 (NR), 1.19 (KL) and 1.36 (IKL), the start's
// transient while the guide's warm-up hands it half the directions, not a runaway (docs/method.md; measured before
// the power's ceiling, with which all three pass the same bound). This miniature does not run away even at power 1;
// runaway_ajar_slow_test.cpp holds the case that does. The old defaults —
// no next-event estimation, a full-scale initial output — swing between 0.5 and 2.2 times the path tracer's to the
// end of the same budget: the last case prints that, as the control the bound is measured against (not asserted).
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
#include "support/image_mean.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

struct Case {
  const char* name;
  radiosity::Method method;
  radiosity::IsLoss is_loss;
  bool old_defaults;  // NEE off and a full-scale initial output (before either existed): expected to swing
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

constexpr long kSteps = 1500, kEvery = 150;

TEST_P(Runaway, ImageMeanStaysNearTheReference) {
  const Case c = GetParam();
  const auto scene = scene::load_scene(fs::path(CLR_SOURCE_DIR) / "scenes" / "door-gap.xml");
  const geometry::Geometry geometry(scene);
  const double want = image_mean(reference(geometry));
  ASSERT_GT(want, 0.0);

  radiosity::TrainConfig config;
  config.steps = kSteps;
  config.method = c.method;
  config.is_loss = c.is_loss;
  config.batch = 2048;
  config.log_every = 1000000;
  config.checkpoint_every = 1000000;
  if (c.old_defaults) {
    config.nee = false;
    config.network["output_init"] = 1.0;
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
    ratios.emplace_back(long(trainer.steps_done()), image_mean(img) / want);
    return image::compare(img, reference(geometry));
  };
  trainer.run(options);
  fs::remove_all(run);

  std::cout << c.name << ": image mean / the path tracer's at steps";
  double worst = 1;
  for (const auto& [step, ratio] : ratios) {
    std::cout << " " << step << ": " << ratio;
    if (step >= kSteps / 5 && std::fabs(ratio - 1) > std::fabs(worst - 1)) worst = ratio;
  }
  std::cout << "\n";
  ASSERT_GE(ratios.size(), 10u);
  if (c.old_defaults) {
    std::cout << c.name << ": the old defaults' worst ratio " << worst << " (not asserted)\n";
    return;
  }
  EXPECT_GT(worst, 0.7) << c.name;
  EXPECT_LT(worst, 1.3) << c.name;
}

INSTANTIATE_TEST_SUITE_P(DoorGap, Runaway,
                         ::testing::Values(Case{"nr", radiosity::Method::Nr, radiosity::IsLoss::Ikl, false},
                                           Case{"isnr_kl", radiosity::Method::Isnr, radiosity::IsLoss::Kl, false},
                                           Case{"isnr_ikl", radiosity::Method::Isnr, radiosity::IsLoss::Ikl, false},
                                           Case{"nr_old_defaults", radiosity::Method::Nr, radiosity::IsLoss::Ikl,
                                                true}),
                         [](const auto& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace clr::test
