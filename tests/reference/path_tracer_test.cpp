// The path tracer's contract: determinism per seed, Mitsuba's max_depth semantics, and the CLI around it.
#include "reference/path_tracer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "geometry/geometry.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

const std::filesystem::path kEnclosure = std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / "furnace-enclosure.xml";

TEST(PathTracer, SameSeedSameImageOtherSeedOtherNoise) {
  const auto scene = scene::load_scene(kEnclosure);
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.spp = 2;
  const auto a = reference::render(geometry, opt), b = reference::render(geometry, opt);
  EXPECT_EQ(a.rgb, b.rgb);
  opt.seed = 1;
  EXPECT_NE(reference::render(geometry, opt).rgb, a.rgb);
}

TEST(PathTracer, MaxDepthCountsPathSegments) {
  // In the enclosure (albedo 1/2, Le = 1 everywhere): 1 segment sees Le; 2 add one bounce, Le·(1 + ρ); 3 add
  // ρ²·Le. Depth 1 involves no randomness at all, so it is exact.
  const auto scene = scene::load_scene(kEnclosure);
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.spp = 16;
  for (const auto& [depth, want] : {std::pair{1, 1.0}, std::pair{2, 1.5}, std::pair{3, 1.75}}) {
    opt.max_depth = depth;
    const auto img = reference::render(geometry, opt);
    double mean = 0;
    for (float v : img.rgb) mean += v / double(img.rgb.size());
    EXPECT_NEAR(mean, want, depth == 1 ? 1e-6 : 0.01 * want) << "max_depth " << depth;
  }
}

class ReferenceCli : public SceneFiles {};

TEST_F(ReferenceCli, WritesTheImageAtTheRequestedSize) {
  const auto out = dir_ / "out.exr";
  const auto r =
      run_cli("reference '" + kEnclosure.string() + "' --spp 2 --width 12 --height 8 -o '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, ::testing::HasSubstr("12x8, 2 spp"));
  const auto img = image::read_exr(out);
  EXPECT_EQ(img.width, 12);
  EXPECT_EQ(img.height, 8);
  // Without a TTY progress is plain lines, ending with the final one.
  EXPECT_THAT(r.err, ::testing::HasSubstr("reference 100.0%"));
  EXPECT_EQ(run_cli("reference '" + kEnclosure.string() + "' -o '" + out.string() + "'").exit_code, 2);  // no --spp
  EXPECT_EQ(run_cli("reference '" + kEnclosure.string() + "' --spp 0 -o '" + out.string() + "'").exit_code, 2);
}

}  // namespace
}  // namespace clr::test
