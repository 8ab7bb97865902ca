// NR and ISNR with the default settings (on PoCL, the N-Module at the CPU width 256) on the Veach scenes, whose
// small, bright emitters make the incident estimate heavy-tailed (slow: about a minute). With the relative residual
// held to the end, Veach Ajar ran away to a uniformly scaled-up solution (a white image, no NaN); the residual now
// fades to L2. Measured after these 300 steps: image mean / Tungsten's = 4.7 (Ajar) and 1.17 (Bidir) with the
// default fade (L2 at the end); at width 512, 4.2 and 1.22, and 1689 for Ajar without the fade
// (`relative_fade_end` 0). 300 steps are early for Ajar (0.99 after the 2866 steps of 5 minutes), so the bound is
// a factor of 10 either way: it tells a run that is settling from one that ran away. (The measurements above are
// vanilla NR's; ISNR's are printed.) With next-event estimation and the N-Module's dark start (2026-11-28): Ajar 1.14
// (NR) and 1.27 (ISNR), Bidir 1.25 and 1.14.
#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/renderer.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"
#include "support/image_mean.hpp"
#include "support/shared_scenes.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

struct Case {
  const char* scene;
  int width, height;  // a divisor of the reference's size, so it box-downsamples exactly
  const char* method;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << " " << c.method; }

class VeachTraining : public ClTest, public ::testing::WithParamInterface<Case> {};

TEST_P(VeachTraining, StaysFiniteAndDoesNotRunAway) {
  const Case c = GetParam();
  const fs::path dir = clr::test::shared_scenes() / c.scene;
  CLR_REQUIRE_SHARED(dir / "scene.xml");
  const auto scene = scene::load_scene(dir / "scene.xml");
  const geometry::Geometry geometry(scene);
  const fs::path run = fs::temp_directory_path() / ("clr_veach_" + std::to_string(::getpid()));
  fs::remove_all(run);
  radiosity::TrainConfig config;
  config.steps = 300;
  config.method = radiosity::parse_method(c.method);
  config.log_every = 1000000;
  config.checkpoint_every = 1000000;
  radiosity::Trainer trainer(ctx(), geometry, config, run, false);
  trainer.run();
  fs::remove_all(run);

  const radiosity::RenderSettings settings{.width = c.width, .height = c.height, .spp = 4};
  const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx(), trainer.network()), settings);
  const auto ref = image::match_size(image::read_exr(dir / "TungstenRender.exr"), img);
  const auto m = image::compare(img, ref);
  const double ratio = image_mean(img) / image_mean(ref);
  std::cout << c.scene << " (" << c.method << "): 300 steps, image mean / Tungsten's " << ratio << ", MAPE " << m.mape
            << "\n";
  EXPECT_EQ(m.non_finite, 0u);
  EXPECT_GT(ratio, 0.1);
  EXPECT_LT(ratio, 10.0);
}

INSTANTIATE_TEST_SUITE_P(Shared, VeachTraining,
                         ::testing::Values(Case{"veach-ajar", 80, 45, "nr"}, Case{"veach-bidir", 64, 64, "nr"},
                                           Case{"veach-ajar", 80, 45, "isnr"}, Case{"veach-bidir", 64, 64, "isnr"}));

}  // namespace
}  // namespace clr::test
