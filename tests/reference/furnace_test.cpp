// Analytic scenes (docs/design.md §8): radiance known in closed form everywhere.
#include <gtest/gtest.h>

#include <iostream>
#include <numeric>

#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(CLR_SOURCE_DIR) / "scenes";

double channel_mean(const image::Image& img, const std::vector<bool>& use) {
  double s = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < use.size(); ++i)
    if (use[i]) {
      s += double(img.rgb[3 * i]) + img.rgb[3 * i + 1] + img.rgb[3 * i + 2];
      n += 3;
    }
  return s / double(n);
}

class Enclosure : public ::testing::TestWithParam<float> {};

TEST_P(Enclosure, RadianceIsEmissionOverOneMinusAlbedo) {
  const float rho = GetParam(), le = 1.0f;
  const auto scene = scene::load_scene(kScenes / "furnace-enclosure.xml", {{"rho", std::to_string(rho)}});
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.spp = 64;
  const auto img = reference::render(geometry, opt);
  const double want = le / (1.0 - rho);
  const std::vector<bool> all(std::size_t(img.width) * std::size_t(img.height), true);
  std::cout << "enclosure rho " << rho << ": mean " << channel_mean(img, all) << ", want " << want << "\n";
  EXPECT_NEAR(channel_mean(img, all), want, 0.01 * want);
  // Every pixel, too: a pixel's 64 paths have a relative spread of ~sqrt(rho/(1-rho))/8, so 4 of those bound it.
  const double tolerance = 4.0 * std::sqrt(rho / (1.0 - rho)) / 8.0;
  for (float v : img.rgb) ASSERT_NEAR(v, want, tolerance * want);
}

INSTANTIATE_TEST_SUITE_P(Albedos, Enclosure, ::testing::Values(0.3f, 0.5f, 0.8f));

TEST(SphereCap, ScatteredRadianceIsUniform) {
  const float rho = 0.5f, le = 1.0f;
  const auto scene = scene::load_scene(kScenes / "furnace-sphere-cap.xml");
  ASSERT_EQ(scene.shapes.size(), 2u);
  const double cap = scene.shapes[0].mesh.area(), rest = scene.shapes[1].mesh.area();
  const double f = cap / (cap + rest);
  EXPECT_NEAR(f, 0.25, 0.005);  // the tessellation keeps the true sphere's area fraction
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.spp = 64;
  const auto img = reference::render(geometry, opt);

  // Classify pixels by what their whole footprint sees (corners and centre), leaving out those on the boundary.
  const auto& cam = scene.camera;
  std::vector<bool> on_cap(img.rgb.size() / 3), on_rest(img.rgb.size() / 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      int hits_cap = 0;
      const float offsets[5][2] = {{0.01f, 0.01f}, {0.99f, 0.01f}, {0.01f, 0.99f}, {0.99f, 0.99f}, {0.5f, 0.5f}};
      for (const auto& o : offsets) {
        const auto r = cam.ray(float(x) + o[0], float(y) + o[1]);
        hits_cap += geometry.intersect({r.origin, r.tnear, r.direction}).shape == 0 ? 1 : 0;
      }
      on_cap[std::size_t(y * img.width + x)] = hits_cap == 5;
      on_rest[std::size_t(y * img.width + x)] = hits_cap == 0;
    }
  ASSERT_GT(std::count(on_cap.begin(), on_cap.end(), true), 100);
  ASSERT_GT(std::count(on_rest.begin(), on_rest.end(), true), 100);
  const double scattered = rho * f * le / (1.0 - rho);
  std::cout << "sphere cap (f = " << f << "): cap " << channel_mean(img, on_cap) << ", want " << le + scattered
            << "; rest " << channel_mean(img, on_rest) << ", want " << scattered << "\n";
  EXPECT_NEAR(channel_mean(img, on_cap), le + scattered, 0.01 * (le + scattered));
  EXPECT_NEAR(channel_mean(img, on_rest), scattered, 0.01 * scattered);
}

}  // namespace
}  // namespace clr::test
