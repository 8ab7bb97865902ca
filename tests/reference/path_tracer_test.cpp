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

// Every sample has its own stream: the first n samples of a longer render are the n of a shorter one, whichever
// render drew them, so that a render continued from its first samples (reference --resume) is the longer render.
// Equal up to the float rounding of the shorter image's mean; a whole render under other thread counts is equal bit
// for bit (its sums are grouped alike).
TEST(PathTracer, ALongerRenderContinuesTheSamplesOfAShorterOne) {
  const auto scene = scene::load_scene(std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml");
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.width = 24;
  opt.height = 16;
  opt.seed = 5;
  opt.spp = 11;
  reference::RenderStats stats;
  const auto whole = reference::render(geometry, opt, &stats);
  EXPECT_EQ(stats.spp, 11);
  opt.spp = 4;
  const auto first = reference::render(geometry, opt);
  opt.first_sample = 4;
  opt.spp = 7;
  const auto rest = reference::render(geometry, opt);
  double worst = 0, total = 0;
  for (std::size_t i = 0; i < whole.rgb.size(); ++i) {
    const double joined = (4.0 * first.rgb[i] + 7.0 * rest.rgb[i]) / 11.0;
    worst = std::max(worst, std::abs(joined - whole.rgb[i]) / (std::abs(whole.rgb[i]) + 1e-3));
    total += whole.rgb[i];
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(total, 0.0);
  // The samples after the first four are other samples: the continued part alone is another image.
  EXPECT_NE(rest.rgb, first.rgb);
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
