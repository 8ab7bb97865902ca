// Real scenes: every scene of the shared corpus of public Mitsuba scenes (../shared/scenes-corpus, its
// manifest.tsv) either path-traces at 32×32 and 1 spp to a finite image, or is refused with an InputError naming
// the feature it needs. Scenes refused today are listed below with the refusal expected; a scene not listed must
// render, and a listed one that renders fails too (take it off the list), so the list only shrinks as features
// land. Out-of-scope scenes (media, curves) are refused for good, and through the CLI with exit 2 and one line.
#include "support/scenes_corpus.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

// Scene folder → a fragment of the refusal expected. Each names the missing (or out-of-scope) feature.
const std::map<std::string, std::string> kRefused = {
    // Out of scope for a surface-only renderer: refused for good.
    {"out-of-scope/mitsuba-data--shape_linearcurve_basic", "curves (hair) are not surfaces"},
    {"out-of-scope/mitsuba-data--test_hetero_sigmat_volpath", "participating media are not modelled"},
};

class ScenesCorpus : public ::testing::TestWithParam<CorpusScene> {};

TEST_P(ScenesCorpus, RendersOrIsRefusedByName) {
  const CorpusScene& c = GetParam();
  if (c.dir.empty()) GTEST_SKIP() << "scene corpus not found at " << kCorpus << " (a shared folder of this project)";
  const fs::path xml = kCorpus / c.dir / c.main_xml;
  const auto refused = kRefused.find(c.dir);
  try {
    const auto scene = scene::load_scene(xml);
    scene::require_emitter(scene, xml);
    scene::require_sensor(scene, xml);
    const geometry::Geometry geometry(scene);
    reference::RenderOptions options;
    options.width = options.height = 32;
    options.spp = 1;
    reference::RenderStats stats;
    const auto image = reference::render(geometry, options, &stats);
    double sum = 0;
    for (float v : image.rgb) sum += v;
    EXPECT_TRUE(std::isfinite(sum));
    EXPECT_EQ(stats.non_finite, 0u);
    EXPECT_EQ(refused, kRefused.end()) << c.dir << " renders now: take it off the list of refused scenes";
  } catch (const InputError& e) {
    ASSERT_NE(refused, kRefused.end()) << c.dir << " is refused: " << e.what();
    EXPECT_THAT(e.what(), ::testing::HasSubstr(refused->second));
    // One line naming the file and line of the element at fault.
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_THAT(e.what(), ::testing::HasSubstr(".xml:"));
  }
}

INSTANTIATE_TEST_SUITE_P(Manifest, ScenesCorpus, ::testing::ValuesIn(corpus_scenes()), corpus_test_name);

// The CLI's side of an out-of-scope scene: exit 2 and a single line naming the feature.
TEST(ScenesCorpusCli, OutOfScopeScenesExitTwoWithOneLine) {
  if (!fs::exists(kCorpus / "manifest.tsv")) GTEST_SKIP() << "scene corpus not found at " << kCorpus;
  for (const auto& c : corpus_scenes()) {
    if (!c.dir.starts_with("out-of-scope/")) continue;
    const auto r = run_cli("reference '" + (kCorpus / c.dir / c.main_xml).string() +
                           "' --spp 1 --width 8 --height 8 -o /tmp/clr_corpus_never_written.exr");
    EXPECT_EQ(r.exit_code, 2) << c.dir << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_THAT(r.err, ::testing::HasSubstr(kRefused.at(c.dir)));
  }
}

// A set assembled elsewhere had folders "scene-init" and "scene_init": one gtest name twice, and every test of the
// binary aborted before it ran.
TEST(CorpusTestNames, FoldersThatDifferOnlyInPunctuationGetDistinctNames) {
  const auto names = corpus_test_names({{"a-b", "x.xml"}, {"a_b", "x.xml"}, {"c", "x.xml"}, {"", ""}});
  EXPECT_EQ(names, (std::vector<std::string>{"a_b_0", "a_b_1", "c", "absent"}));
}

}  // namespace
}  // namespace clr::test
