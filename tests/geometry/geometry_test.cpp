// Embree tracing (single and batched, closest and any hit, alpha masks) and area-uniform surface sampling.
#include "geometry/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/pcg32.hpp"
#include "geometry/surface_sampler.hpp"
#include "image/image.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using geometry::Ray;
using scene::Vec3;

class Geometry : public SceneFiles {};

TEST_F(Geometry, ClosestHitFindsThePointItsAttributesAndItsSide) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
    <shape type="cube"><transform name="to_world"><translate z="-5"/></transform></shape>)"));
  const geometry::Geometry g(s);
  const auto hit = g.intersect({Vec3(0.5f, -0.5f, 3.0f), 0.0f, Vec3(0, 0, -1)});
  ASSERT_TRUE(hit.valid());
  EXPECT_EQ(hit.shape, 0u);
  EXPECT_NEAR(hit.t, 3.0f, 1e-6f);
  const auto p = g.surface(hit);
  EXPECT_NEAR(glm::length(p.position - Vec3(0.5f, -0.5f, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(p.at.uv.x, 0.75f, 1e-6f);  // Mitsuba's rectangle uv: ((x+1)/2, (y+1)/2)
  EXPECT_NEAR(p.at.uv.y, 0.25f, 1e-6f);
  EXPECT_NEAR(p.frame.n.z, 1.0f, 1e-6f);
  EXPECT_NEAR(std::abs(p.geometric_normal.z), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(geometry::emitted(s, p, Vec3(0, 0, 1)).x, 2.0f);   // the front emits
  EXPECT_FLOAT_EQ(geometry::emitted(s, p, Vec3(0, 0, -1)).x, 0.0f);  // the back does not
  // Beside both shapes: nothing; behind the rectangle: the cube.
  EXPECT_EQ(g.intersect({Vec3(0.5f, 1.5f, 3.0f), 0.0f, Vec3(0, 0, -1)}).shape, geometry::kNoHit);
  const auto behind = g.intersect({Vec3(0.5f, 0.5f, -1.0f), 0.0f, Vec3(0, 0, -1)});
  EXPECT_EQ(behind.shape, 1u);
  EXPECT_NEAR(behind.t, 3.0f, 1e-5f);
  EXPECT_TRUE(g.occluded({Vec3(0, 0, 1), 0.0f, Vec3(0, 0, -1), 2.0f}));
  EXPECT_FALSE(g.occluded({Vec3(0, 0, 1), 0.0f, Vec3(0, 0, -1), 0.5f}));
}

TEST_F(Geometry, BumpMapsTiltTheShadingNormalByTheHeightGradient) {
  // Height 0 at u = 0.25 rising to 1 at u = 0.75 (bilinear between two texels): dh/du = 2. On the rectangle
  // dp/du = (2, 0, 0), so the bumped tangent is (2, 0, 2·scale) and the normal leans back along −x.
  image::Image ramp(2, 1);
  for (int c = 0; c < 3; ++c) ramp.pixel(1, 0)[c] = 1.0f;
  image::write_png(dir_ / "ramp.png", ramp);
  const auto s = scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="bumpmap">
    <texture name="map" type="bitmap"><string name="filename" value="ramp.png"/></texture>
    <float name="scale" value="0.5"/><bsdf type="diffuse"/></bsdf></shape>)"));
  const geometry::Geometry g(s);
  const auto p = g.surface(g.intersect({Vec3(0, 0.3f, 1), 0.0f, Vec3(0, 0, -1)}));
  const Vec3 want = glm::normalize(Vec3(-1, 0, 2));  // cross((2, 0, 1), (0, 2, 0)) ∝ (−2, 0, 4)
  EXPECT_NEAR(glm::length(p.frame.n - want), 0.0f, 1e-3f);
  EXPECT_NEAR(p.geometric_normal.z, 1.0f, 1e-6f);  // geometry itself is untouched
}

TEST_F(Geometry, BatchesAnswerLikeSingleRays) {
  const auto s = scene::load_scene(scene(R"(<shape type="sphere"/>
    <shape type="cube"><transform name="to_world"><scale value="3"/></transform></shape>)"));
  const geometry::Geometry g(s);
  std::vector<Ray> rays(20000);
  Pcg32 rng(0, 5);
  for (auto& r : rays) {
    r.origin = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 4.0f - 2.0f;
    r.direction = scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
    r.tfar = 4.0f * rng.next_float();
  }
  std::vector<geometry::Hit> hits(rays.size());
  std::vector<std::uint8_t> blocked(rays.size());
  g.intersect(rays, hits);
  g.occluded(rays, blocked);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto h = g.intersect(rays[i]);
    ASSERT_EQ(hits[i].shape, h.shape) << i;
    ASSERT_EQ(hits[i].prim, h.prim) << i;
    ASSERT_EQ(hits[i].t, h.t) << i;
    ASSERT_EQ(blocked[i] != 0, h.valid()) << i;
  }
}

TEST_F(Geometry, MasksCutHolesWithTheirOpacity) {
  for (float opacity : {0.0f, 0.3f, 1.0f}) {
    const auto s = scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="mask">
      <float name="opacity" value=")" + std::to_string(opacity) +
                                           R"("/><bsdf type="diffuse"/></bsdf></shape>)"));
    const geometry::Geometry g(s);
    Pcg32 rng(1, 2);
    constexpr int kRays = 20000;
    int hits = 0, blocked = 0;
    for (int i = 0; i < kRays; ++i) {
      const Ray r{Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.0f), 0.0f, Vec3(0, 0, -1)};
      hits += g.intersect(r).valid() ? 1 : 0;
      blocked += g.occluded(r) ? 1 : 0;
    }
    const double sd = std::sqrt(opacity * (1 - opacity) / kRays);
    EXPECT_NEAR(double(hits) / kRays, opacity, 4 * sd + 1e-9) << opacity;
    EXPECT_EQ(hits, blocked) << "a ray sees the same holes whether it asks for the closest or any hit";
  }
}

TEST_F(Geometry, SurfaceSamplesAreUniformByAreaOverNonDeltaSurfaces) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="2"/><translate z="3"/></transform>
      <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></shape>
    <shape type="sphere"><transform name="to_world"><translate z="-3"/></transform><bsdf type="dielectric"/></shape>)"));
  const geometry::SurfaceSampler sampler(s);
  EXPECT_NEAR(sampler.total_area(), 20.0, 1e-4);  // 4 + 16; the glass sphere is not sampled
  constexpr std::size_t kN = 200000;
  const auto samples = sampler.sample(42, kN);
  std::size_t on_large = 0;
  double sum_x = 0, sum_x2 = 0;
  for (const auto& smp : samples) {
    ASSERT_LT(smp.point.shape, 2u);
    const auto& shape = s.shapes[smp.point.shape];
    EXPECT_EQ(smp.material, std::uint32_t(shape.material));
    if (smp.point.shape == 1) {
      ++on_large;
      ASSERT_NEAR(smp.point.position.z, 3.0f, 1e-5f);
      EXPECT_FLOAT_EQ(smp.roughness, 0.3f);
    } else {
      ASSERT_NEAR(smp.point.position.z, 0.0f, 1e-6f);
      EXPECT_FLOAT_EQ(smp.albedo.y, 0.4f);
      EXPECT_FLOAT_EQ(smp.roughness, 1.0f);
      sum_x += smp.point.position.x;
      sum_x2 += double(smp.point.position.x) * smp.point.position.x;
    }
  }
  const double p = 0.8, sd = std::sqrt(p * (1 - p) / kN);
  EXPECT_NEAR(double(on_large) / kN, p, 4 * sd);
  // Uniform on [-1, 1]: mean 0, second moment 1/3 (standard errors ~0.0045 and ~0.003 with 40k samples).
  const double n_small = double(kN - on_large);
  EXPECT_NEAR(sum_x / n_small, 0.0, 0.02);
  EXPECT_NEAR(sum_x2 / n_small, 1.0 / 3.0, 0.015);
  // Reproducible for a seed, different across seeds.
  const auto again = sampler.sample(42, 100), other = sampler.sample(43, 100);
  for (std::size_t i = 0; i < 100; ++i) EXPECT_EQ(again[i].point.position, samples[i].point.position);
  EXPECT_NE(other[0].point.position, samples[0].point.position);
}

}  // namespace
}  // namespace clr::test
