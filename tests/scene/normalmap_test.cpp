// Mitsuba's `normalmap` and the shading frame anisotropic lobes need: both follow dp/du of the uv map.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/surface.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::Vec2;
using scene::Vec3;

class ShadingFrames : public SceneFiles {};

void expect_vec(const Vec3& a, const Vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST_F(ShadingFrames, NormalMapsTiltTheNormalInTheTangentFrame) {
  const float s30 = 0.5f, c30 = std::sqrt(3.0f) / 2;
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><bsdf type="normalmap">
      <texture type="rawconstant" name="normalmap"><vector name="value" value="0.5, 0.5, 1"/></texture>
      <bsdf type="diffuse"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="normalmap">
      <texture type="rawconstant" name="normalmap"><vector name="value" value=")" +
                                         std::to_string(0.5f + 0.5f * s30) + ", 0.5, " +
                                         std::to_string(0.5f + 0.5f * c30) + R"("/></texture>
      <bsdf type="diffuse"/></bsdf>
      <transform name="to_world"><rotate z="1" angle="90"/></transform></shape>)"));
  const auto flat = geometry::surface_point(s, 0, 0, Vec2(0.2f, 0.3f));
  expect_vec(flat.frame.n, Vec3(0, 0, 1));  // the identity map
  expect_vec(flat.frame.s, Vec3(1, 0, 0));  // dp/du of the rectangle's uv
  // Rotated by 90° about z, dp/du points along +y: a normal tilted 30° towards +u tilts towards +y.
  const auto tilted = geometry::surface_point(s, 1, 0, Vec2(0.2f, 0.3f));
  expect_vec(tilted.frame.n, Vec3(0, s30, c30), 1e-4f);
  EXPECT_NEAR(glm::dot(tilted.frame.n, tilted.frame.s), 0.0f, 1e-6f);
}

TEST_F(ShadingFrames, AnisotropicLobesAlignWithDpDu) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><bsdf type="roughconductor">
      <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/></bsdf>
      <transform name="to_world"><rotate z="1" angle="90"/></transform></shape>)"));
  const auto p = geometry::surface_point(s, 0, 1, Vec2(0.3f, 0.3f));
  expect_vec(p.frame.s, Vec3(0, 1, 0));
  expect_vec(p.frame.n, Vec3(0, 0, 1));
}

}  // namespace
}  // namespace clr::test
