// Point, spot, directional and projector lights (Mitsuba's delta emitters): what arrives from each, as Mitsuba
// defines it, and the path tracer against closed forms — a point light at the centre of a diffuse sphere and a
// directional light on a diffuse plane.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::DeltaLight;
using scene::Rgb;
using scene::Vec3;

class DeltaLights : public SceneFiles {
 protected:
  // Mean of every channel of a reference render.
  double mean_radiance(const scene::Scene& s, int spp, int size = 16) const {
    const geometry::Geometry g(s);
    reference::RenderOptions o;
    o.width = o.height = size;
    o.spp = spp;
    const auto img = reference::render(g, o);
    double sum = 0;
    for (float v : img.rgb) sum += v;
    return sum / double(img.rgb.size());
  }
};

TEST_F(DeltaLights, PointLightAtTheCentreOfADiffuseSphere) {
  // Every bounce inside a closed sphere of albedo ρ spreads evenly: L = ρ·I / (π R² (1 − ρ)).
  const auto s = scene::load_scene(scene(R"(
    <emitter type="point"><point name="position" value="1, 2, 3"/><rgb name="intensity" value="3"/></emitter>
    <shape type="sphere"><point name="center" value="1, 2, 3"/><float name="radius" value="2"/>
      <boolean name="flip_normals" value="true"/>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <sensor type="perspective"><float name="fov" value="60"/>
      <transform name="to_world"><lookat origin="1, 2, 3" target="1, 2, 4" up="0, 1, 0"/></transform></sensor>)"));
  ASSERT_EQ(s.delta_lights.size(), 1u);
  const double want = 0.5 * 3.0 / (scene::kPi * 4.0 * 0.5);
  EXPECT_NEAR(mean_radiance(s, 256), want, 0.02 * want);
}

// A light placed exactly on a surface (a public scene's spot nested in a shape sits at the origin, on its floor)
// lights what it sees: the shadow ray stops just short of the light, not on the surface under it, which float
// rounding put in front of the light for most rays (that scene rendered 5.9 times darker than in Mitsuba, which
// stops its shadow rays short too). A wall at x = 1 seen around (1, 0, 1), the point light at the origin on a black
// floor (z = 0): L = ρ/π · I · cos θ / d² with d² = 2 and cos θ = 1/√2.
TEST_F(DeltaLights, ALightOnASurfaceLightsWhatItSees) {
  const auto s = scene::load_scene(scene(R"(
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <emitter type="point"><point name="position" value="0, 0, 0"/><rgb name="intensity" value="10"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="5"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-90"/><translate x="1" z="1"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <sensor type="perspective"><float name="fov" value="1"/>
      <transform name="to_world"><lookat origin="-1, 0, 1" target="1, 0, 1" up="0, 0, 1"/></transform></sensor>)"));
  const double want = 0.5 / scene::kPi * 10 * (1 / std::sqrt(2.0)) / 2;
  EXPECT_NEAR(mean_radiance(s, 16, 8), want, 0.02 * want);
}

// Each emitter kind delivers its analytic power: inside a closed diffuse sphere (radius R, albedo ρ) the light
// reflected off the walls spreads evenly (any patch sees every other in proportion to its area), so a wall the
// emitter does not reach directly shows L = ρ²Φ / (4π²R²(1 − ρ)), Φ being the power the emitter sends out. A lamp
// whose direct light is even (a sphere light at the centre) shows ρΦ / (4π²R²(1 − ρ)) everywhere.
class EmitterPower : public DeltaLights {
 protected:
  static constexpr double kRadius = 2, kAlbedo = 0.5;
  // The enclosure around `light` (at the origin), seen from (0, 0, eye_z) looking along −z.
  scene::Scene enclosure(const std::string& light, const std::string& name, int eye_z = 0) const {
    return scene::load_scene(scene(light + R"(
      <shape type="sphere"><float name="radius" value="2"/><boolean name="flip_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
      <sensor type="perspective"><float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0, 0, )" +
                                       std::to_string(eye_z) +
                                       R"(" target="0, 0, -2" up="0, 1, 0"/></transform></sensor>)",
                                   "3.0.0", name));
  }
  static double indirect(double power) {
    return kAlbedo * kAlbedo * power / (4 * scene::kPi * scene::kPi * kRadius * kRadius * (1 - kAlbedo));
  }
};

TEST_F(EmitterPower, SpotSendsOutItsIntegratedCone) {
  // Mitsuba's spot: I inside the beam (15°), falling linearly in angle to 0 at the cutoff (20°). Φ = 2π I ∫ f(θ) sinθ.
  const double beam = 15 * scene::kPi / 180, cutoff = 20 * scene::kPi / 180, intensity = 30;
  double integral = 0;
  constexpr int kSteps = 100000;
  for (int i = 0; i < kSteps; ++i) {
    const double t = (i + 0.5) * cutoff / kSteps, f = t < beam ? 1.0 : (cutoff - t) / (cutoff - beam);
    integral += f * std::sin(t) * cutoff / kSteps;
  }
  const auto s = enclosure(R"(<emitter type="spot"><rgb name="intensity" value="30"/>
      <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform></emitter>)",
                           "spot.xml");
  const double want = indirect(2 * scene::kPi * intensity * integral);
  const double got = mean_radiance(s, 1024);
  std::cout << "spot: " << got << ", want " << want << "\n";
  EXPECT_NEAR(got, want, 0.03 * want);
}

TEST_F(EmitterPower, ProjectorSendsOutItsImage) {
  // Its power from the irradiance it lays on a facing plane (π·scale·E / z² over the frustum's section, 60° wide,
  // as the loaded light's own aspect): integrated over the plane z = 1 numerically.
  const auto s = enclosure(R"(<emitter type="projector"><rgb name="irradiance" value="0.5"/>
      <float name="scale" value="4"/><float name="fov" value="60"/>
      <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform></emitter>)",
                           "projector.xml");
  const DeltaLight& l = s.delta_lights.at(0);
  double power = 0;
  constexpr int kCells = 1000;
  constexpr double kHalf = 1.5;  // the plane's half-width at z = 1, wider than the 60° frustum
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      const Vec3 p(float(-kHalf + (i + 0.5) * 2 * kHalf / kCells), float(-kHalf + (j + 0.5) * 2 * kHalf / kCells), 1);
      const auto a = l.arrive(p);
      power += double(a.radiance.x) * -double(a.direction.z) * (2 * kHalf / kCells) * (2 * kHalf / kCells);
    }
  EXPECT_GT(power, 0.0);
  const double want = indirect(power), got = mean_radiance(s, 1024);
  std::cout << "projector: " << got << ", want " << want << "\n";
  EXPECT_NEAR(got, want, 0.03 * want);
}

TEST_F(EmitterPower, SphereLightSendsOutRadianceTimesPiTimesItsArea) {
  // An area light of radiance Le on a sphere of radius r: Φ = Le·π·4πr², its direct light even on the walls.
  const auto s = enclosure(R"(<shape type="sphere"><float name="radius" value="0.1"/>
      <emitter type="area"><rgb name="radiance" value="20"/></emitter></shape>)",
                           "area.xml", -1);  // looking away from the lamp, from outside it
  const double power = 20 * scene::kPi * 4 * scene::kPi * 0.01;
  const double want = indirect(power) / kAlbedo;  // direct and reflected: ρΦ / (4π²R²(1 − ρ))
  const double got = mean_radiance(s, 256);
  std::cout << "sphere light: " << got << ", want " << want << "\n";
  EXPECT_NEAR(got, want, 0.02 * want);
}

TEST_F(DeltaLights, DirectionalLightOnADiffusePlane) {
  // One bounce: L = ρ/π · E · cos θ, the same for every sample (the light's only share is chosen with probability 1).
  const auto s = scene::load_scene(scene(R"(
    <emitter type="directional"><vector name="direction" value="0.5, 0, -0.8660254"/>
      <rgb name="irradiance" value="2, 4, 6"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="100"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <sensor type="perspective"><float name="fov" value="20"/>
      <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>)"));
  const double want = 0.5 / scene::kPi * 4.0 * 0.8660254;  // mean of the channels 2, 4, 6
  EXPECT_NEAR(mean_radiance(s, 4), want, 1e-3 * want);
}

TEST(DeltaLightArrival, PointAndDirectional) {
  DeltaLight point;
  point.position = Vec3(0, 0, 3);
  point.intensity = Rgb(9.0f);
  const auto a = point.arrive(Vec3(0, 0, 0));
  EXPECT_FLOAT_EQ(a.distance, 3.0f);
  EXPECT_FLOAT_EQ(a.radiance.x, 1.0f);  // I / d²
  EXPECT_FLOAT_EQ(a.direction.z, 1.0f);
  DeltaLight sun;
  sun.kind = DeltaLight::Kind::directional;
  sun.direction = Vec3(0, -1, 0);
  sun.intensity = Rgb(2.0f);
  const auto b = sun.arrive(Vec3(5, 5, 5));
  EXPECT_TRUE(std::isinf(b.distance));
  EXPECT_FLOAT_EQ(b.direction.y, 1.0f);
  EXPECT_FLOAT_EQ(b.radiance.x, 2.0f);
}

TEST_F(DeltaLights, SpotFallsOffLinearlyInAngle) {
  const auto s = scene::load_scene(scene(R"(
    <emitter type="spot"><rgb name="intensity" value="4"/>
      <float name="cutoff_angle" value="30"/><float name="beam_width" value="20"/>
      <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform></emitter>)"));
  const DeltaLight& l = s.delta_lights.at(0);
  auto at_angle = [&](float degrees) {
    const float t = degrees * scene::kPi / 180.0f;
    return l.arrive(Vec3(2 * std::tan(t), 0, 0)).radiance.x * (4 + 4 * std::tan(t) * std::tan(t));  // × d²
  };
  EXPECT_NEAR(at_angle(0), 4.0f, 1e-4f);
  EXPECT_NEAR(at_angle(15), 4.0f, 1e-4f);               // within the beam
  EXPECT_NEAR(at_angle(25), 2.0f, 1e-3f);               // half-way between beam and cutoff
  EXPECT_NEAR(at_angle(31), 0.0f, 1e-6f);               // beyond the cutoff
  EXPECT_EQ(l.arrive(Vec3(0, 0, 4)).radiance.x, 0.0f);  // behind
  // Defaults: cutoff 20°, beam 15°.
  const auto d = scene::load_scene(scene(R"(<emitter type="spot"/>)")).delta_lights.at(0);
  EXPECT_NEAR(d.cutoff, 20.0f * scene::kPi / 180.0f, 1e-6f);
  EXPECT_NEAR(d.beam_width, 15.0f * scene::kPi / 180.0f, 1e-6f);
}

TEST_F(DeltaLights, ProjectorLightsAFacingPlaneEvenly) {
  const auto s = scene::load_scene(scene(R"(
    <emitter type="projector"><rgb name="irradiance" value="0.5"/><float name="scale" value="2"/>
      <float name="fov" value="60"/>
      <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform></emitter>)"));
  const DeltaLight& l = s.delta_lights.at(0);
  // On the plane z = 2 facing it, radiance · cos (what a diffuse surface there integrates) is π·scale·E / z².
  for (const float x : {0.0f, 0.5f, 1.0f}) {
    const auto a = l.arrive(Vec3(x, 0.3f, 2));
    EXPECT_NEAR(a.radiance.x * -a.direction.z, scene::kPi * 2 * 0.5f / 4, 1e-4f) << x;
  }
  EXPECT_EQ(l.arrive(Vec3(2, 0, 2)).radiance.x, 0.0f);  // outside its 60° image
  EXPECT_EQ(l.arrive(Vec3(0, 0, -2)).radiance.x, 0.0f);
}

TEST_F(DeltaLights, LoaderReadsTheirProperties) {
  const auto file = scene(R"(
    <emitter type="point"><transform name="to_world"><translate x="1" y="2" z="3"/></transform></emitter>
    <emitter type="directional"><transform name="to_world"><lookat origin="0, 0, 0" target="0, -1, 0" up="0, 0, 1"/>
      </transform></emitter>
    <shape type="rectangle"/>)");
  const auto s = scene::load_scene(file);
  ASSERT_EQ(s.delta_lights.size(), 2u);
  EXPECT_FLOAT_EQ(s.delta_lights[0].position.z, 3.0f);
  EXPECT_NEAR(s.delta_lights[1].direction.y, -1.0f, 1e-6f);
  EXPECT_NO_THROW(scene::require_emitter(s, file));
  EXPECT_THROW(scene::load_scene(scene(R"(<emitter type="projector"/>)")), InputError);  // needs an irradiance
  EXPECT_THROW(scene::load_scene(scene(R"(<emitter type="spot"><float name="beam_width" value="30"/></emitter>)")),
               InputError);  // wider than the cutoff
}

}  // namespace
}  // namespace clr::test

namespace clr::test {
namespace {

class TexturedEmitters : public SceneFiles {};

TEST_F(TexturedEmitters, AreaRadianceFollowsItsTexture) {
  // An orthographic view framing a rectangle whose radiance is a 4 × 4 checkerboard of 2 and 0: each pixel (8 per
  // cell) sees one cell, so the image holds 2 and 0 in equal parts.
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><emitter type="area"><texture type="checkerboard" name="radiance">
      <rgb name="color0" value="2"/><rgb name="color1" value="0"/>
      <transform name="to_uv"><scale value="2"/></transform></texture></emitter></shape>
    <sensor type="orthographic">
      <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
      <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
        <rfilter type="box"/></film></sensor>)"));  // a box filter: a pixel's samples stay in its cell
  ASSERT_TRUE(s.shapes[0].radiance_texture.has_value());
  EXPECT_FLOAT_EQ(s.shapes[0].radiance.x, 1.0f);  // its mean
  const geometry::Geometry g(s);
  reference::RenderOptions o;
  o.spp = 1;
  o.max_depth = 1;
  const auto img = reference::render(g, o);
  int bright = 0;
  for (float v : img.rgb) {
    EXPECT_TRUE(v == 0.0f || v == 2.0f) << v;
    bright += v == 2.0f;
  }
  EXPECT_EQ(bright, int(img.rgb.size()) / 2);
}

}  // namespace
}  // namespace clr::test
