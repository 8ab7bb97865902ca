// Mitsuba's thinlens and orthographic sensors: where their rays start and go.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::Vec2;
using scene::Vec3;

class Sensors : public SceneFiles {};

void expect_vec(const Vec3& a, const Vec3& b, float tol = 1e-4f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST_F(Sensors, ThinLensRaysMeetAtTheFocalPlane) {
  const auto s = scene::load_scene(scene(R"(<sensor type="thinlens">
      <float name="aperture_radius" value="0.2"/><float name="focus_distance" value="5"/><float name="fov" value="40"/>
      <transform name="to_world"><translate x="1" y="2" z="3"/></transform>
      <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="16"/></film>
    </sensor>)"));
  const auto& c = s.camera;
  EXPECT_FLOAT_EQ(c.aperture_radius, 0.2f);
  for (const Vec2 pixel : {Vec2(3.5f, 2.5f), Vec2(16, 8), Vec2(30.2f, 15.1f)}) {
    const auto pin = c.ray(pixel.x, pixel.y);  // the aperture's centre: the pinhole ray
    const Vec3 focus = pin.origin + pin.direction * (5.0f / pin.direction.z);
    for (const Vec2 lens : {Vec2(0.1f, 0.9f), Vec2(0.8f, 0.3f), Vec2(0.99f, 0.5f)}) {
      const auto r = c.ray(pixel.x, pixel.y, lens);
      EXPECT_NEAR(r.origin.z, 3.0f, 1e-5f);
      EXPECT_LE(glm::length(Vec2(r.origin) - Vec2(1, 2)), 0.2f + 1e-5f);   // on the aperture
      expect_vec(r.origin + r.direction * (5.0f / r.direction.z), focus);  // through the same focal point
    }
  }
  EXPECT_THROW(scene::load_scene(scene(R"(<sensor type="thinlens"/>)")), InputError);  // needs an aperture
}

// The mitsuba-blender exporter writes principal_point_offset_x/y on every perspective camera: a lens shift by those
// fractions of the film, so the ray through (px, py) is the unshifted camera's ray through (px + x·W, py + y·H), at
// any film size.
TEST_F(Sensors, PrincipalPointOffsetShiftsTheImagePlane) {
  const std::string camera = R"(<float name="fov" value="50"/>
      <transform name="to_world"><lookat origin="1, 2, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
      <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film>)";
  const auto plain = scene::load_scene(scene("<sensor type=\"perspective\">" + camera + "</sensor>", "3.0.0", "a.xml"));
  const auto shifted = scene::load_scene(scene(R"(<sensor type="perspective">
      <float name="principal_point_offset_x" value="0.25"/><float name="principal_point_offset_y" value="-0.1"/>)" +
                                                   camera + "</sensor>",
                                               "3.0.0", "b.xml"));
  EXPECT_EQ(shifted.camera.principal_point_offset, Vec2(0.25f, -0.1f));
  for (const int scale : {1, 3}) {
    const auto a = plain.camera.resized(40 * scale, 20 * scale), b = shifted.camera.resized(40 * scale, 20 * scale);
    for (const Vec2 pixel : {Vec2(0.5f, 0.5f), Vec2(20, 10), Vec2(37.3f, 18.9f)}) {
      const Vec2 p = pixel * float(scale);
      const auto r = b.ray(p.x, p.y), want = a.ray(p.x + 0.25f * float(a.width), p.y - 0.1f * float(a.height));
      expect_vec(r.origin, want.origin);
      expect_vec(r.direction, want.direction);
    }
  }
  // Another view (render --camera) looks through its centre.
  const float view[] = {0, 0, 5, 0, 0, 0, 0, 1, 0, 40};
  const auto v = shifted.camera.pinhole_view(view, "--camera");
  expect_vec(v.ray(20, 10).direction, Vec3(0, 0, -1));
}

TEST_F(Sensors, OrthographicRaysAreParallel) {
  const auto s = scene::load_scene(scene(R"(<sensor type="orthographic">
      <float name="near_clip" value="0.5"/>
      <transform name="to_world"><scale x="2" y="2" z="1"/><translate z="-1"/></transform>
      <film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="10"/></film>
    </sensor>)"));
  const auto& c = s.camera;
  const auto corner = c.ray(0, 0), centre = c.ray(10, 5);
  expect_vec(corner.origin, Vec3(2, 1, -1));  // +x to the image's left, half as tall as wide
  expect_vec(centre.origin, Vec3(0, 0, -1));
  expect_vec(corner.direction, Vec3(0, 0, 1));
  EXPECT_NEAR(corner.tnear, 0.5f, 1e-6f);
}

TEST_F(Sensors, OrthographicViewOfALitPlane) {
  // Every pixel sees the plane lit by a directional light: ρ/π · E · cos θ exactly.
  const auto s = scene::load_scene(scene(R"(
    <emitter type="directional"><vector name="direction" value="0, 0, -1"/><rgb name="irradiance" value="3"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <sensor type="orthographic">
      <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>)"));
  const geometry::Geometry g(s);
  reference::RenderOptions o;
  o.width = o.height = 8;
  o.spp = 2;
  const auto img = reference::render(g, o);
  for (float v : img.rgb) EXPECT_NEAR(v, 0.5f / scene::kPi * 3.0f, 1e-5f);
}

}  // namespace
}  // namespace clr::test
