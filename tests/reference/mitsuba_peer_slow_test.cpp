// Mitsuba 3 as an independent peer (skipped where `import mitsuba` fails): the same scene files rendered by
// mitsuba_render.py with Mitsuba's path tracer at the same size, spp and max_depth must agree with ours within
// 1 % (channel means) and 2 % (median 8×8-block error), widened by the noise of both renders. The shared scenes, and
// the bundled scenes written for features the shared ones lack (exact cylinders and disks, a sunsky).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "geometry/geometry.hpp"
#include "reference/agreement.hpp"
#include "reference/mitsuba_peer.hpp"
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

void expect_agreement(const std::filesystem::path& file, const Case& c) {
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

  const auto p = mitsuba_render(file, c.width, c.height, c.spp / 2, scene.max_depth, 1);
  const auto q = mitsuba_render(file, c.width, c.height, c.spp / 2, scene.max_depth, 2);
  ASSERT_TRUE(p && q) << "Mitsuba 3 cannot load " << file;
  const PeerVerdict v = judge_against_peer(a, b, *p, *q);
  std::cout << c.scene << " vs Mitsuba 3, " << c.width << "x" << c.height << ", " << c.spp << " spp: " << v << "\n";
  EXPECT_TRUE(v.agrees()) << v;
}

std::string test_name(const ::testing::TestParamInfo<Case>& param_info) {
  std::string name = param_info.param.scene;
  name = name.substr(0, name.find('.'));
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

class MitsubaPeer : public ::testing::TestWithParam<Case> {};

TEST_P(MitsubaPeer, AgreesWithinNoise) {
  const std::filesystem::path file = clr::test::shared_scenes() / GetParam().scene / "scene.xml";
  CLR_REQUIRE_SHARED(file);
  if (!have_mitsuba()) GTEST_SKIP() << "Mitsuba 3 is not installed (pip install mitsuba)";
  expect_agreement(file, GetParam());
}

class MitsubaPeerBundled : public ::testing::TestWithParam<Case> {};

TEST_P(MitsubaPeerBundled, AgreesWithinNoise) {
  if (!have_mitsuba()) GTEST_SKIP() << "Mitsuba 3 is not installed (pip install mitsuba)";
  expect_agreement(std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / GetParam().scene, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Shared, MitsubaPeer,
                         ::testing::Values(Case{"cornell-box", 128, 128, 512}, Case{"veach-bidir", 128, 128, 1024},
                                           Case{"veach-ajar", 160, 90, 1024}, Case{"staircase", 72, 128, 512}),
                         test_name);
INSTANTIATE_TEST_SUITE_P(Bundled, MitsubaPeerBundled,
                         ::testing::Values(Case{"exact-shapes.xml", 64, 64, 1024}, Case{"sunsky.xml", 64, 64, 1024}),
                         test_name);

}  // namespace
}  // namespace clr::test
