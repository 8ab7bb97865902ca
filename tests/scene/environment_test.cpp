// Environment emitters: importance sampling of the lat-long map against its pdf, and the lookup convention.
#include "scene/environment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "image/image.hpp"
#include "scene/chi2.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::Vec3;

class Environment : public SceneFiles {};

TEST_F(Environment, EnvmapSamplesFollowTheirPdf) {
  // A dim map with a bright spot and a gradient, rotated so that the test does not ride on the identity frame.
  image::Image img(24, 12);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) img.pixel(x, y)[c] = 0.1f + 0.05f * float(x) + (x == 5 && y == 3 ? 40.0f : 0.0f);
  image::write_exr(dir_ / "env.exr", img);
  const glm::mat4 rotation = glm::mat4(glm::mat3(glm::vec3(0, 0, 1), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)));
  const auto env = scene::Environment::envmap(dir_ / "env.exr", 1.0f, rotation);
  // sample() reports the pdf of the pixel it drew from and the radiance there; looking its direction up again lands
  // in a neighbouring pixel only when float rounding moves it across a pixel edge.
  std::size_t mismatched = 0;
  const auto r = chi2_test(
      [&](Pcg32& rng) -> std::optional<Vec3> {
        const auto s = env.sample({rng.next_float(), rng.next_float()});
        if (std::abs(s.pdf - env.pdf(s.dir)) > 1e-3f * s.pdf ||
            glm::length(s.radiance - env.eval(s.dir)) > 1e-3f * glm::length(s.radiance))
          ++mismatched;
        return s.dir;
      },
      [&](const Vec3& w) { return double(env.pdf(w)); }, 1'000'000, 1, 96);
  // 96 quadrature nodes a cell and axis: the table's cells now reach a texel's neighbours, so the spot spreads its
  // density's steps over more cells than the default 24 nodes integrate closely. (Seeds 1–6 give p = 0.76, 0.76,
  // 0.84, 0.48, 0.34, 0.35; seed 11, this test's before the table changed, 0.0076: one draw in a hundred.)
  ASSERT_TRUE(r.problem.empty()) << r.problem;
  EXPECT_GT(r.p_value, 0.01) << "dof " << r.dof;
  EXPECT_LT(mismatched, 1000u);
  // The spot is where the map says: pixel (5, 3) is u = 5.5/24 (column centres), v = 3/11 (rows from pole to pole)
  // in the emitter's frame. Between texels the map is interpolated bilinearly, as Mitsuba 3 looks it up, wrapping
  // around in u.
  const auto at = [&](float u, float v) {
    const float phi = 2 * scene::kPi * u, theta = scene::kPi * v;
    const Vec3 local(std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta));
    return env.eval(glm::mat3(rotation) * local).x;
  };
  EXPECT_NEAR(at(5.5f / 24, 3.0f / 11), 40.35f, 1e-3f);
  EXPECT_NEAR(at(6.0f / 24, 3.0f / 11), 0.5f * (40.35f + 0.4f), 1e-3f);
  EXPECT_NEAR(at(5.5f / 24, 3.5f / 11), 0.5f * (40.35f + 0.35f), 1e-3f);
  EXPECT_NEAR(at(0.0f, 7.0f / 11), 0.5f * (0.1f + (0.1f + 0.05f * 23)), 1e-4f);
}

// Where Mitsuba 3 places an envmap's texels: an 8 × 4 map whose red channel is the texel's row and green its column,
// looked up at the directions of (u, v), gives what Mitsuba 3.9.1's own envmap eval gives there (measured with
// scalar_rgb): rows at v = i / 3 from pole to pole, columns at u = (j + ½) / 8, wrapping around between the last and
// the first.
TEST_F(Environment, TexelsSitWhereMitsubaPutsThem) {
  image::Image img(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      img.pixel(x, y)[0] = float(y);
      img.pixel(x, y)[1] = float(x);
      img.pixel(x, y)[2] = 1.0f;
    }
  image::write_exr(dir_ / "grid.exr", img);
  const auto env = scene::Environment::envmap(dir_ / "grid.exr", 1.0f, glm::mat4(1.0f));
  const auto at = [&](double u, double v) {
    const double phi = 2 * M_PI * u, theta = M_PI * v;
    return env.eval(
        Vec3(float(std::sin(phi) * std::sin(theta)), float(std::cos(theta)), float(-std::cos(phi) * std::sin(theta))));
  };
  // Mitsuba's red at u = 0.3 and v = 1/6, 1/3, 1/2, 2/3, 1.
  const std::pair<double, float> rows[] = {{1.0 / 6, 0.5f}, {1.0 / 3, 1.0f}, {0.5, 1.5f}, {2.0 / 3, 2.0f}, {1.0, 3.0f}};
  for (const auto& [v, red] : rows) EXPECT_NEAR(at(0.3, v).x, red, 1e-3f) << "v " << v;
  // Mitsuba's green at v = 1/2 and u = 1/16, 1/8, 1/4, 1/2, 15/16, and across the seam at u = 0.
  const std::pair<double, float> columns[] = {{1.0 / 16, 0.0f}, {1.0 / 8, 0.5f},   {0.25, 1.5f},
                                              {0.5, 3.5f},      {15.0 / 16, 7.0f}, {1e-4, 3.5f}};
  for (const auto& [u, green] : columns) EXPECT_NEAR(at(u, 0.5).y, green, 2e-2f) << "u " << u;
}

TEST_F(Environment, ConstantIsUniform) {
  const auto env = scene::Environment::constant(scene::Rgb(0.5f));
  const auto r = chi2_test(
      [&](Pcg32& rng) -> std::optional<Vec3> {
        return env.sample({rng.next_float(), rng.next_float()}).dir;
      },
      [&](const Vec3& w) { return double(env.pdf(w)); }, 200'000, 12);
  EXPECT_GT(r.p_value, 0.01);
}

}  // namespace
}  // namespace clr::test
