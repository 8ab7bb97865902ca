// The scenes of ../shared/scenes against Tungsten's independent renders at reduced resolution (slow: minutes).
// "Agree within the noise": two renders with different seeds measure our own noise per 8×8 block and in the image
// mean; the bounds of the fast Cornell test (1 % mean, 2 % median block error) are widened by that noise, so a
// noisy scene (Veach's, lit through caustics and a door gap) is held to what its spp can resolve, and no more.
#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/geometry.hpp"
#include "reference/agreement.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

struct Case {
  const char* scene;
  int width, height, spp;
};

// Block sums (all channels) of 8×8 blocks.
std::vector<double> block_sums(const image::Image& img) {
  std::vector<double> out;
  for (int by = 0; by + 8 <= img.height; by += 8)
    for (int bx = 0; bx + 8 <= img.width; bx += 8) {
      double s = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) s += double(img.pixel(x, y)[0]) + img.pixel(x, y)[1] + img.pixel(x, y)[2];
      out.push_back(s / (3 * 64));
    }
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

class TungstenScene : public ::testing::TestWithParam<Case> {};

TEST_P(TungstenScene, AgreesWithinNoise) {
  const Case c = GetParam();
  const std::filesystem::path dir = std::filesystem::path(CLR_SHARED_SCENES) / c.scene;
  if (!std::filesystem::exists(dir / "scene.xml")) GTEST_SKIP() << "no " << dir;
  const auto scene = scene::load_scene(dir / "scene.xml");
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.width = c.width;
  opt.height = c.height;
  opt.spp = c.spp / 2;
  reference::RenderStats stats_a, stats_b;
  opt.seed = 1;
  const auto a = reference::render(geometry, opt, &stats_a);
  opt.seed = 2;
  const auto b = reference::render(geometry, opt, &stats_b);
  EXPECT_EQ(stats_a.non_finite + stats_b.non_finite, 0u);
  image::Image img = a;
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
  const auto ref = image::match_size(image::read_exr(dir / "TungstenRender.exr"), img);
  const Agreement ag = agreement(img, ref);

  // Noise of the averaged image: half the difference of the two halves, per block and in each channel mean.
  const auto sa = block_sums(a), sb = block_sums(b), sr = block_sums(ref);
  std::vector<double> noise(sa.size());
  for (std::size_t i = 0; i < sa.size(); ++i) noise[i] = std::abs(sa[i] - sb[i]) / 2 / (sr[i] + 0.01);
  const double block_noise = median(noise);
  double mean_noise = 0;
  const double n = double(a.width) * a.height;
  for (int ch = 0; ch < 3; ++ch) {
    double diff = 0;
    for (std::size_t i = ch; i < a.rgb.size(); i += 3) diff += (double(a.rgb[i]) - b.rgb[i]) / n;
    mean_noise = std::max(mean_noise, std::abs(diff) / 2 / ag.ref_mean[std::size_t(ch)]);
  }
  std::cout << c.scene << " " << c.width << "x" << c.height << ", " << c.spp << " spp, "
            << stats_a.seconds + stats_b.seconds << " s: " << ag << "; own noise: mean " << 100 * mean_noise
            << " %, median block " << 100 * block_noise << " %\n";
  // 3× the measured mean noise (itself a one-sample estimate) and 2× the block noise's median on top of the bounds.
  EXPECT_LT(ag.worst_mean_error, 0.01 + 3 * mean_noise) << ag;
  EXPECT_LT(ag.median_block_error, 0.02 + 2 * block_noise) << ag;
}

INSTANTIATE_TEST_SUITE_P(Shared, TungstenScene,
                         ::testing::Values(Case{"cornell-box", 128, 128, 1024}, Case{"veach-bidir", 128, 128, 2048},
                                           Case{"veach-ajar", 160, 90, 2048}),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           std::string name = param_info.param.scene;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// Every shared scene (the staircase: Mitsuba 0.5, 774 OBJ meshes, textures) loads and renders finite, non-negative.
TEST(SharedScenes, RenderWithoutNaN) {
  for (const char* name : {"cornell-box", "veach-bidir", "veach-ajar", "staircase"}) {
    const std::filesystem::path file = std::filesystem::path(CLR_SHARED_SCENES) / name / "scene.xml";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
    const auto scene = scene::load_scene(file);
    const geometry::Geometry geometry(scene);
    reference::RenderOptions opt;
    opt.width = scene.camera.width / 8;
    opt.height = scene.camera.height / 8;
    opt.spp = 16;
    reference::RenderStats stats;
    const auto img = reference::render(geometry, opt, &stats);
    EXPECT_EQ(stats.non_finite, 0u) << name;
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0) << name;
    double sum = 0;
    for (float v : img.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << name << " rendered black";
  }
}

}  // namespace
}  // namespace clr::test
