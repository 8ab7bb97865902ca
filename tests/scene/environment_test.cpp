// Environment emitters: importance sampling of the lat-long map against its pdf, and the lookup convention.
#include "scene/environment.hpp"

#include <gtest/gtest.h>

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
      [&](const Vec3& w) { return double(env.pdf(w)); }, 1'000'000, 11);
  ASSERT_TRUE(r.problem.empty()) << r.problem;
  EXPECT_GT(r.p_value, 0.01) << "dof " << r.dof;
  EXPECT_LT(mismatched, 1000u);
  // The spot is where the map says: pixel (5, 3) is u = 5.5/24, v = 3.5/12 in the emitter's frame. Between texel
  // centres the map is interpolated bilinearly, as Mitsuba 3 looks it up, wrapping around in u.
  const auto at = [&](float u, float v) {
    const float phi = 2 * scene::kPi * u, theta = scene::kPi * v;
    const Vec3 local(std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta));
    return env.eval(glm::mat3(rotation) * local).x;
  };
  EXPECT_NEAR(at(5.5f / 24, 3.5f / 12), 40.35f, 1e-4f);
  EXPECT_NEAR(at(6.0f / 24, 3.5f / 12), 0.5f * (40.35f + 0.4f), 1e-3f);
  EXPECT_NEAR(at(5.5f / 24, 4.0f / 12), 0.5f * (40.35f + 0.35f), 1e-3f);
  EXPECT_NEAR(at(0.0f, 7.5f / 12), 0.5f * (0.1f + (0.1f + 0.05f * 23)), 1e-4f);
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
