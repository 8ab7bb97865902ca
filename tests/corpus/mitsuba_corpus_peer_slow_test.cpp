// Mitsuba 3 as the peer of every corpus scene (../shared/scenes-corpus) that both renderers load: our path tracer
// and Mitsuba's (tests/reference/mitsuba_render.py, scalar_rgb) at a low resolution and the same spp and max_depth
// agree within the bounds of mitsuba_peer_slow_test.cpp — 1 % on the channel means and 2 % on the median 8×8-block
// error, widened by the noise of both renders (mitsuba_peer.hpp). Scenes we refuse are the corpus test's business;
// scenes Mitsuba cannot load (the script exits 3) have no peer. Skipped where `import mitsuba` fails or the corpus is
// absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "reference/agreement.hpp"
#include "reference/mitsuba_peer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/scenes_corpus.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
constexpr int kSize = 48, kSpp = 256;  // the longer side; samples per pixel of each renderer

class MitsubaCorpusPeer : public ::testing::TestWithParam<CorpusScene> {};

TEST_P(MitsubaCorpusPeer, AgreesWithinNoise) {
  const CorpusScene& c = GetParam();
  if (c.dir.empty()) GTEST_SKIP() << "scene corpus not found at " << kCorpus;
  if (!have_mitsuba()) GTEST_SKIP() << "Mitsuba 3 is not installed (pip install mitsuba)";
  const fs::path xml = kCorpus / c.dir / c.main_xml;
  std::optional<scene::Scene> loaded;
  try {
    loaded = scene::load_scene(xml);
    scene::require_emitter(*loaded, xml);
    scene::require_sensor(*loaded, xml);
  } catch (const InputError& e) {
    GTEST_SKIP() << "refused (the corpus test checks why): " << e.what();
  }
  const scene::Scene& scene = *loaded;
  // The film's aspect at a low resolution, so that both cameras keep the same field of view.
  const int W = scene.camera.width, H = scene.camera.height;
  const int width = W >= H ? kSize : std::max(8, int(std::lround(double(kSize) * W / H)));
  const int height = W >= H ? std::max(8, int(std::lround(double(kSize) * H / W))) : kSize;

  const auto p = mitsuba_render(xml, width, height, kSpp / 2, scene.max_depth, 1);
  if (!p) GTEST_SKIP() << "Mitsuba 3 cannot load " << xml;
  const auto q = mitsuba_render(xml, width, height, kSpp / 2, scene.max_depth, 2);
  ASSERT_TRUE(q);

  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.width = width;
  opt.height = height;
  opt.spp = kSpp / 2;
  opt.seed = 1;
  const auto a = reference::render(geometry, opt);
  opt.seed = 2;
  const auto b = reference::render(geometry, opt);
  const PeerVerdict v = judge_against_peer(a, b, *p, *q);
  std::cout << c.dir << " vs Mitsuba 3, " << width << "x" << height << ", " << kSpp << " spp: " << v << "\n";
  EXPECT_TRUE(v.agrees()) << v;
}

INSTANTIATE_TEST_SUITE_P(Corpus, MitsubaCorpusPeer, ::testing::ValuesIn(corpus_scenes()), corpus_test_name);

}  // namespace
}  // namespace clr::test
