// Mitsuba 3 as an independent peer (skipped where `import mitsuba` fails): the same scene files rendered by
// mitsuba_render.py with Mitsuba's path tracer at the same size, spp and max_depth must agree with ours within
// 1 % (channel means) and 2 % (median 8×8-block error), widened by the noise of both renders.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

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

  const auto p = mitsuba_render(file, c.width, c.height, c.spp / 2, scene.max_depth, 1);
  const auto q = mitsuba_render(file, c.width, c.height, c.spp / 2, scene.max_depth, 2);
  ASSERT_TRUE(p && q) << "Mitsuba 3 cannot load " << file;
  const PeerVerdict v = judge_against_peer(a, b, *p, *q);
  std::cout << c.scene << " vs Mitsuba 3, " << c.width << "x" << c.height << ", " << c.spp << " spp: " << v << "\n";
  EXPECT_TRUE(v.agrees()) << v;
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
