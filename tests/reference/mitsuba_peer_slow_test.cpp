// Mitsuba 3 as an independent peer (skipped where `import mitsuba` fails): the same scene files rendered by
// mitsuba_render.py with Mitsuba's path tracer at the same size, spp and max_depth must agree with ours within
// 1 % (channel means) and 2 % (median 8×8-block error), widened by the noise of both renders.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "geometry/geometry.hpp"
#include "reference/agreement.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/shared_scenes.hpp"

namespace clr::test {
namespace {

struct Case {
  const char* scene;
  int width, height, spp;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

bool have_mitsuba() { return std::system("python3 -c 'import mitsuba' >/dev/null 2>&1") == 0; }

class MitsubaPeer : public ::testing::TestWithParam<Case> {};

TEST_P(MitsubaPeer, AgreesWithinNoise) {
  const Case c = GetParam();
  const std::filesystem::path file = clr::test::shared_scenes() / c.scene / "scene.xml";
  CLR_REQUIRE_SHARED(file);
  if (!have_mitsuba()) GTEST_SKIP() << "Mitsuba 3 is not installed (pip install mitsuba)";
  const auto scene = scene::load_scene(file);
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.width = c.width;
  opt.height = c.height;
  opt.spp = c.spp / 2;
  opt.seed = 1;
  const auto a = reference::render(geometry, opt);
  opt.seed = 2;
  const auto b = reference::render(geometry, opt);

  const auto out = std::filesystem::temp_directory_path() / ("clr_mitsuba_" + std::to_string(::getpid()) + ".exr");
  const std::string cmd = "python3 '" CLR_SOURCE_DIR "/tests/reference/mitsuba_render.py' '" + file.string() + "' " +
                          std::to_string(c.width) + " " + std::to_string(c.height) + " " + std::to_string(c.spp) + " " +
                          std::to_string(scene.max_depth) + " '" + out.string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto peer = image::read_exr(out);
  std::filesystem::remove(out);

  const auto img = average(a, b);
  const Agreement ag = agreement(img, peer);
  const Noise noise = noise_of_average(a, b, peer);
  std::cout << c.scene << " vs Mitsuba 3, " << c.width << "x" << c.height << ", " << c.spp << " spp: " << ag
            << "; own noise: mean " << 100 * noise.mean << " %, median block " << 100 * noise.median_block << " %\n";
  // The peer's noise is like ours at equal spp, so the difference carries √2 times our noise.
  EXPECT_LT(ag.worst_mean_error, 0.01 + 3 * std::sqrt(2.0) * noise.mean) << ag;
  EXPECT_LT(ag.median_block_error, 0.02 + 2 * std::sqrt(2.0) * noise.median_block) << ag;
}

INSTANTIATE_TEST_SUITE_P(Shared, MitsubaPeer,
                         ::testing::Values(Case{"cornell-box", 128, 128, 512}, Case{"veach-bidir", 128, 128, 1024},
                                           Case{"veach-ajar", 160, 90, 1024}, Case{"staircase", 72, 128, 512}),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           std::string name = param_info.param.scene;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace clr::test
