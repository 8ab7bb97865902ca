// Mitsuba 3 as an independent peer (skipped where `import mitsuba` fails): the same scene files rendered by
// mitsuba_render.py with Mitsuba's path tracer at the same size and max_depth, each side with 10 seeds, judged as the
// corpus peer judges (peer_judgement.hpp): channel means within 0.2 % plus three standard errors of the ratio, the
// median 8×8-block error within 1 % plus three of its own, the spp raised where the noise would let a 0.5 % bias
// pass. The shared scenes, and the bundled scenes written for features the shared ones lack (exact cylinders and
// disks, a sunsky).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <iostream>
#include <string>

#include "geometry/geometry.hpp"
#include "reference/mitsuba_peer.hpp"
#include "reference/peer_judgement.hpp"
#include "scene/scene.hpp"
#include "support/shared_scenes.hpp"

namespace clr::test {
namespace {

struct Case {
  const char* scene;
  int width, height;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

// Measured 2026-11-28 apart from the test's own seeds: 48², seeds 101–104 × 1024 spp a side, σ 0.03 % (the test's
// seeds at 128 spp gave +0.06 / +0.27 / +0.51 %, σ 0.05 %); docs/scenes.md, "Sun and sky".
constexpr KnownDifference kKnown[] = {
    {"sunsky.xml",
     {0.0019, 0.0039, 0.0062},
     "the sun: its power integrated from the Hosek-Wilkie authors' data, where Mitsuba's table of the same integral "
     "sits 0.35-0.39 % lower"},
};

void expect_agreement(const std::filesystem::path& file, const Case& c) {
  const auto scene = scene::load_scene(file);
  const geometry::Geometry geometry(scene);
  const PeerPlan plan;
  const KnownDifference* known = known_difference(kKnown, c.scene);
  const SeedVerdict v =
      run_peer(our_seeds(geometry, c.width, c.height), mitsuba_seeds(file, c.width, c.height, scene.max_depth), plan,
               known ? known->expected : std::array<double, 3>{});
  std::cout << c.scene << " vs Mitsuba 3, " << c.width << "x" << c.height << ": " << v << "\n";
  if (known) std::cout << "  known difference: " << known->reason << "\n";
  if (v.widest_bound() > plan.target_bound)
    std::cout << "  the bound stays above " << 100 * plan.target_bound << " % within the cap (" << plan.max_spp
              << " spp, " << plan.final_seconds << " s of processor time): a 0.5 % bias could pass here\n";
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
                         ::testing::Values(Case{"cornell-box", 64, 64}, Case{"veach-bidir", 64, 64},
                                           Case{"veach-ajar", 80, 45}, Case{"staircase", 36, 64}),
                         test_name);
INSTANTIATE_TEST_SUITE_P(Bundled, MitsubaPeerBundled,
                         ::testing::Values(Case{"exact-shapes.xml", 48, 48}, Case{"sunsky.xml", 48, 48}), test_name);

}  // namespace
}  // namespace clr::test
