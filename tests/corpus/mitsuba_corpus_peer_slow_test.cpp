// Mitsuba 3 as the peer of every corpus scene (../shared/scenes-corpus, or the folder CLRADIOSITY_SCENES_CORPUS names)
// that both renderers load: our path tracer and Mitsuba's (tests/reference/mitsuba_render.py, scalar_rgb) at a low
// resolution and the same spp and max_depth, each with 10 seeds, agree in the channel means within 0.2 % plus three
// standard errors of the ratio, and in the median 8×8-block error within 1 % plus three of its standard errors
// (peer_judgement.hpp); a scene whose noise would leave the mean bound above 0.4 % is rendered again at a higher spp,
// so that a 0.5 % bias fails. Scenes with a known, documented difference (docs/scenes.md) are judged around it, each
// named below with its reason. Scenes we refuse are the corpus test's business; scenes Mitsuba cannot load (the
// script exits 3) have no peer. Skipped where `import mitsuba` fails or the corpus is absent.
//
// With CLRADIOSITY_PEER_TSV set, each scene's verdict is appended to that file as a row (the results tables of
// docs/results/scenes.md): folder, size, seeds, spp per seed, ours / Mitsuba's for R, G and B, then for the worst
// channel its letter, ratio − 1, σ, each side's σ, expected difference and bound, then the median block error, its
// σ and bound, pass or FAIL, and seconds.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "reference/mitsuba_peer.hpp"
#include "reference/peer_judgement.hpp"
#include "scene/scene.hpp"
#include "support/scenes_corpus.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
constexpr int kSize = 48;  // pixels on the longer side

// Differences between the two renderers that are understood (docs/scenes.md, "The corpus peer's bounds").
constexpr KnownDifference kKnown[] = {
    // Measured 2026-11-28 at 48², 10 seeds × 1024 spp a side (σ 0.05 %), and again apart from the test's seeds
    // (101–106 × 1024 spp: +0.13 / +0.71 / +0.76 %, σ 0.10 %); with Mitsuba's quadrature in ours the scene agrees
    // within 0.03 %, as does the scene with a smooth `plastic` for the rough one (−0.13 %).
    {"mitsuba-data--test_surf_area_light_volpath",
     {0.0010, 0.0066, 0.0069},
     "its roughplastic (beckmann 0.1, diffuse 0.2, 0.7, 0.7): Mitsuba 3 takes the substrate's internal reflectance "
     "2 int R(mu) mu dmu as the mean of 64 points over [0, 1], ends included, 1.9 % below the integral (smooth "
     "interface), so its diffuse lobe is 2.7 % darker than ours; at alpha -> 0 Mitsuba's roughplastic loses 2 % in a "
     "furnace where its smooth plastic does not"},
};

void append_row(const std::string& dir, int width, int height, const SeedVerdict& v, double seconds) {
  const char* file = std::getenv("CLRADIOSITY_PEER_TSV");
  if (!file || !*file) return;
  std::ofstream out(file, std::ios::app);
  const int w = v.worst();
  out << dir << '\t' << width << 'x' << height << '\t' << v.seeds << '\t' << v.spp << '\t' << 1 + v.ratio[0] << '\t'
      << 1 + v.ratio[1] << '\t' << 1 + v.ratio[2] << '\t' << "RGB"[w] << '\t' << v.ratio[w] << '\t' << v.sigma[w]
      << '\t' << v.sigma_ours[w] << '\t' << v.sigma_peer[w] << '\t' << v.expected[w] << '\t' << v.bound[w] << '\t'
      << v.block_error << '\t' << v.block_sigma << '\t' << v.block_bound << '\t' << (v.agrees() ? "pass" : "FAIL")
      << '\t' << seconds << '\n';
}

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

  if (!mitsuba_renders(xml, width, height, 1, scene.max_depth, 0, 1)) GTEST_SKIP() << "Mitsuba 3 cannot load " << xml;

  const auto start = std::chrono::steady_clock::now();
  const geometry::Geometry geometry(scene);
  const PeerPlan plan;
  const KnownDifference* known = known_difference(kKnown, c.dir);
  const SeedVerdict v = run_peer(our_seeds(geometry, width, height), mitsuba_seeds(xml, width, height, scene.max_depth),
                                 plan, known ? known->expected : std::array<double, 3>{});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  append_row(c.dir, width, height, v, seconds);
  std::cout << c.dir << " vs Mitsuba 3, " << width << "x" << height << ": " << v << "; " << seconds << " s\n";
  if (known) std::cout << "  known difference: " << known->reason << "\n";
  if (v.widest_bound() > plan.target_bound)
    std::cout << "  the bound stays above " << 100 * plan.target_bound << " % within the cap (" << plan.max_spp
              << " spp, " << plan.final_seconds << " s of processor time): a 0.5 % bias could pass here\n";
  EXPECT_TRUE(v.agrees()) << v;
}

INSTANTIATE_TEST_SUITE_P(Corpus, MitsubaCorpusPeer, ::testing::ValuesIn(corpus_scenes()), corpus_test_name);

}  // namespace
}  // namespace clr::test
