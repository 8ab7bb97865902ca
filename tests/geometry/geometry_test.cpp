// Embree tracing (single and batched, closest and any hit, alpha masks, exact spheres) and area-uniform surface
// sampling.
#include "geometry/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/pcg32.hpp"
#include "geometry/light_sampler.hpp"
#include "geometry/surface_sampler.hpp"
#include "image/image.hpp"
#include "scene/chi2.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using geometry::Ray;
using scene::Vec2;
using scene::Vec3;

class Geometry : public SceneFiles {
 protected:
  // A rectangle bump-mapped by a ramp: height 0 at u = 0.25 rising to 1 at u = 0.75 (bilinear between two texels),
  // so dh/du = 2, at scale 0.5 over a diffuse BSDF.
  scene::Scene ramp_bumped_rectangle() const {
    image::Image ramp(2, 1);
    for (int c = 0; c < 3; ++c) ramp.pixel(1, 0)[c] = 1.0f;
    image::write_png(dir_ / "ramp.png", ramp);
    return scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="bumpmap">
      <texture name="map" type="bitmap"><string name="filename" value="ramp.png"/></texture>
      <float name="scale" value="0.5"/><bsdf type="diffuse"/></bsdf></shape>)"));
  }
};

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
  // dh/du = 2 and, on the rectangle, dp/du = (2, 0, 0): the bumped tangent is (2, 0, 2·scale) and the normal leans
  // back along −x.
  const auto s = ramp_bumped_rectangle();
  const geometry::Geometry g(s);
  const auto p = g.surface(g.intersect({Vec3(0, 0.3f, 1), 0.0f, Vec3(0, 0, -1)}));
  const Vec3 want = glm::normalize(Vec3(-1, 0, 2));  // cross((2, 0, 1), (0, 2, 0)) ∝ (−2, 0, 4)
  EXPECT_NEAR(glm::length(p.frame.n - want), 0.0f, 1e-3f);
  EXPECT_NEAR(p.geometric_normal.z, 1.0f, 1e-6f);  // geometry itself is untouched
}

// As in Mitsuba's bumpmap and normalmap, a tilted shading frame passes no light across the normal it tilted: the
// BSDF is zero for an incident direction on one side of the tilted normal and the other side of the untilted one,
// which a frame tilted by 26.6° (the ramp above) otherwise reflected from below the surface (a bump-mapped glass
// rendered 14 % brighter than in Mitsuba, and a diffuse one let light through).
TEST_F(Geometry, TiltedFramesPassNoLightAcrossTheUntiltedNormal) {
  const auto s = ramp_bumped_rectangle();
  const geometry::Geometry g(s);
  const auto p = g.surface(g.intersect({Vec3(0, 0.3f, 1), 0.0f, Vec3(0, 0, -1)}));
  const auto bsdf = p.bsdf(s);
  const Vec3 wo = glm::normalize(Vec3(-1, 0, 3));  // above both normals
  const Vec3 above_both = glm::normalize(Vec3(0, 0.2f, 1)), above_tilted_only = glm::normalize(Vec3(-1, 0, -0.2f)),
             above_untilted_only = glm::normalize(Vec3(1, 0, 0.2f));
  EXPECT_GT(bsdf.eval(wo, above_both).x, 0.0f);
  EXPECT_GT(bsdf.pdf(wo, above_both), 0.0f);
  for (const Vec3& wi : {above_tilted_only, above_untilted_only}) {
    EXPECT_EQ(bsdf.eval(wo, wi).x, 0.0f);
    EXPECT_EQ(bsdf.pdf(wo, wi), 0.0f);
  }
  Pcg32 rng(3, 4);
  int kept = 0;
  constexpr int kDraws = 4000;
  for (int i = 0; i < kDraws; ++i) {
    const auto d = bsdf.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!d) continue;
    ++kept;
    EXPECT_GT(glm::dot(d->wi, p.frame.n) * glm::dot(d->wi, p.geometric_normal), 0.0f);
  }
  // Cosine-weighted about the tilted normal, the share below the untilted one is (1 − cos 26.6°)/2 ≈ 5 %.
  EXPECT_NEAR(double(kept) / kDraws, 0.947, 0.015);
}

// A flat height field keeps the shading normal a mesh interpolates (Mitsuba replaces the tangents' components along
// it): the bump once rebuilt the normal from the triangle's own tangents, which turned a smooth mesh faceted.
TEST_F(Geometry, BumpMapsKeepTheInterpolatedNormalWhereTheHeightIsFlat) {
  image::Image flat(2, 2);
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) flat.pixel(i % 2, i / 2)[c] = 0.5f;
  image::write_png(dir_ / "flat.png", flat);
  write("tri.obj",
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nvn -0.3 0 1\nvn 0.3 0 1\nvn 0 0.3 1\n"
        "f 1/1/1 2/2/2 3/3/3\n");
  const auto s = scene::load_scene(scene(R"(<shape type="obj"><string name="filename" value="tri.obj"/>
    <bsdf type="bumpmap"><texture name="map" type="bitmap"><string name="filename" value="flat.png"/></texture>
    <float name="scale" value="2"/><bsdf type="diffuse"/></bsdf></shape>)"));
  const geometry::Geometry g(s);
  const auto p = g.surface(g.intersect({Vec3(0.5f, -0.5f, 1), 0.0f, Vec3(0, 0, -1)}));
  // Barycentric weights there: 1/8, 5/8 and 1/4 of the (unit) vertex normals.
  const Vec3 want =
      glm::normalize(0.125f * glm::normalize(Vec3(-0.3f, 0, 1)) + 0.625f * glm::normalize(Vec3(0.3f, 0, 1)) +
                     0.25f * glm::normalize(Vec3(0, 0.3f, 1)));
  EXPECT_NEAR(glm::length(p.frame.n - want), 0.0f, 1e-4f);
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

// Spheres are intersected exactly (an Embree user geometry in double precision), at any scale and offset, from
// outside and from inside, with Mitsuba's uv.
TEST_F(Geometry, SpheresAreHitExactlyAtEveryScale) {
  for (const double scale : {1e-4, 1.0, 1e4}) {
    const Vec3 c = Vec3(1, 2, 3) * float(scale) + Vec3(float(37 * scale), 0, 0);
    const float r = 0.5f * float(scale);
    const auto s =
        scene::load_scene(scene(R"(<shape type="sphere"><point name="center" x=")" + std::to_string(c.x) + R"(" y=")" +
                                std::to_string(c.y) + R"(" z=")" + std::to_string(c.z) +
                                R"("/><float name="radius" value=")" + std::to_string(r) + R"("/></shape>)"));
    ASSERT_TRUE(s.shapes[0].exact) << "a sphere is kept exact";
    ASSERT_TRUE(s.shapes[0].mesh.triangles.empty());
    const Vec3 centre = s.shapes[0].exact->origin;
    const geometry::Geometry g(s);
    Pcg32 rng(3, 9);
    for (int i = 0; i < 2000; ++i) {
      // From a point 3 radii out towards a random point on the sphere's disk: a hit at the analytic distance.
      const Vec3 from = centre + 3.0f * r * scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
      const Vec3 aim = centre + 0.99f * r * scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
      const Vec3 dir = glm::normalize(aim - from);
      const glm::dvec3 oc = glm::dvec3(from) - glm::dvec3(centre), d(dir);
      const double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - double(r) * r);
      const double want = -b - std::sqrt(disc);
      const auto hit = g.intersect({from, 0.0f, dir});
      ASSERT_TRUE(hit.valid()) << scale << " " << i;
      ASSERT_NEAR(hit.t, want, 1e-5 * r) << scale << " " << i;
      const auto p = g.surface(hit);
      ASSERT_NEAR(glm::length(p.position - centre), r, 2e-6f * (r + glm::length(centre)));
      ASSERT_NEAR(glm::length(p.geometric_normal - (p.position - centre) / r), 0.0f, 1e-4f);
      ASSERT_NEAR(glm::dot(p.frame.n, p.geometric_normal), 1.0f, 1e-6f);
      // Leaving the surface: outwards nothing is hit, inwards the far side at the chord's length.
      const Vec3 out = glm::normalize(p.geometric_normal + 0.999f * glm::cross(p.geometric_normal, dir));
      ASSERT_FALSE(g.intersect({p.spawn_origin(out), 0.0f, out}).valid()) << scale << " " << i;
      const auto far = g.intersect({p.spawn_origin(dir), 0.0f, dir});
      ASSERT_TRUE(far.valid()) << scale << " " << i;
      // Off by the spawn offset, which is relative to the coordinates' magnitude (the centre lies 37 radii out).
      ASSERT_NEAR(far.t, -2.0 * glm::dot(glm::dvec3(p.position - centre), d), 1e-3 * p.extent) << scale << " " << i;
    }
  }
}

TEST_F(Geometry, SpheresKeepMitsubasUvAndNormalsUnderEveryPlacement) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="sphere"><float name="radius" value="2"/></shape>
    <shape type="sphere"><transform name="to_world"><rotate x="1" angle="90"/><scale value="3"/>
      <translate x="10"/></transform><boolean name="flip_normals" value="true"/></shape>
    <shape type="sphere"><transform name="to_world"><scale x="1" y="1" z="1.5"/></transform></shape>
    <shape type="shapegroup" id="g"><shape type="sphere"/></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale value="0.5"/><translate y="-10"/>
      </transform></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale x="2"/><translate y="10"/>
      </transform></shape>)"));
  ASSERT_EQ(s.shapes.size(), 5u);
  const geometry::Geometry g(s);
  // u = φ/2π from +x towards +y, v = θ/π from +z: +x is (0, ½), +y (¼, ½), the top (·, 0).
  auto at = [&](const Vec3& from, const Vec3& dir) { return g.surface(g.intersect({from, 0.0f, dir})); };
  const auto px = at(Vec3(5, 0, 0), Vec3(-1, 0, 0)), py = at(Vec3(0, 5, 0), Vec3(0, -1, 0)),
             pz = at(Vec3(0, 0, 5), Vec3(0, 0, -1));
  EXPECT_NEAR(px.at.uv.x, 0.0f, 1e-6f);
  EXPECT_NEAR(px.at.uv.y, 0.5f, 1e-6f);
  EXPECT_NEAR(py.at.uv.x, 0.25f, 1e-6f);
  EXPECT_NEAR(py.at.uv.y, 0.5f, 1e-6f);
  EXPECT_NEAR(pz.at.uv.y, 0.0f, 1e-6f);
  EXPECT_NEAR(px.position.x, 2.0f, 1e-6f);
  // Rotated 90° about x: its local +z points along world −y, so the point nearest −y is its pole; flipped normals
  // face the centre.
  ASSERT_TRUE(s.shapes[1].exact);
  EXPECT_NEAR(s.shapes[1].area(), 4 * M_PI * 9, 1e-3);
  const auto pole = at(Vec3(10, -5, 0), Vec3(0, 1, 0));
  EXPECT_EQ(pole.shape, 1u);
  EXPECT_NEAR(pole.at.uv.y, 0.0f, 1e-6f);
  EXPECT_NEAR(pole.position.y, -3.0f, 1e-5f);
  EXPECT_NEAR(pole.geometric_normal.y, 1.0f, 1e-6f);
  // A stretched sphere is an ellipsoid: tessellated.
  EXPECT_FALSE(s.shapes[2].exact);
  EXPECT_GT(s.shapes[2].mesh.triangles.size(), 1000u);
  // Instances: a uniform scale keeps the sphere exact, a stretch tessellates that copy only.
  ASSERT_TRUE(s.shapes[3].exact);
  EXPECT_NEAR(s.shapes[3].exact->radius(), 0.5f, 1e-7f);
  EXPECT_NEAR(at(Vec3(0, -10, 5), Vec3(0, 0, -1)).position.z, 0.5f, 1e-6f);
  EXPECT_FALSE(s.shapes[4].exact);
  EXPECT_NEAR(at(Vec3(5, 10, 0), Vec3(-1, 0, 0)).position.x, 2.0f, 1e-4f);
  // The tangents a bump map and an anisotropic lobe are oriented by: ∂p/∂u along +φ, ∂p/∂v along +θ.
  Vec3 dpdu, dpdv;
  s.shapes[0].exact->tangents(Vec2(0.25f, 0.5f), dpdu, dpdv);
  EXPECT_NEAR(glm::length(dpdu - Vec3(-4 * M_PI, 0, 0)), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::length(dpdv - Vec3(0, 0, -2 * M_PI)), 0.0f, 1e-4f);
}

TEST_F(Geometry, TenThousandSpheresCostNoTessellation) {
  // 10 000 small spheres on a grid: each is one primitive (a tessellated one was 262 144 triangles, 100 of them
  // ~4 GB); every ray down a column hits the sphere it aims at.
  std::string shapes;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      shapes += R"(<shape type="sphere"><point name="center" x=")" + std::to_string(i) + R"(" y=")" +
                std::to_string(j) + R"(" z="0"/><float name="radius" value="0.25"/></shape>)";
  const auto s = scene::load_scene(scene(shapes));
  ASSERT_EQ(s.shapes.size(), 10000u);
  std::size_t triangles = 0;
  for (const auto& shape : s.shapes) triangles += shape.mesh.triangles.size();
  EXPECT_EQ(triangles, 0u);
  const geometry::Geometry g(s);
  Pcg32 rng(5, 1);
  for (int k = 0; k < 5000; ++k) {
    const int i = int(rng.next_float() * 100), j = int(rng.next_float() * 100);
    const float dx = 0.2f * (rng.next_float() - 0.5f), dy = 0.2f * (rng.next_float() - 0.5f);
    const auto hit = g.intersect({Vec3(float(i) + dx, float(j) + dy, 5.0f), 0.0f, Vec3(0, 0, -1)});
    ASSERT_EQ(hit.shape, std::uint32_t(100 * i + j));
    ASSERT_NEAR(hit.t, 5.0f - std::sqrt(0.0625f - dx * dx - dy * dy), 1e-5f);
  }
}

TEST_F(Geometry, SphereSamplesAreUniformByAreaAndTheLightDensityMatches) {
  const auto s = scene::load_scene(scene(R"(<shape type="sphere"><transform name="to_world"><rotate y="1" angle="30"/>
      <scale value="0.5"/><translate x="2"/></transform>
      <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"));
  const geometry::SurfaceSampler sampler(s);
  EXPECT_NEAR(sampler.total_area(), M_PI, 1e-5);
  // χ² over 8 × 8 cells equal in area (cos θ and φ about the sphere's centre, in world axes): 63 degrees of
  // freedom, whose 99.9 % quantile is 103.4.
  constexpr int kCells = 8;
  constexpr std::size_t kN = 128000;
  std::vector<double> count(kCells * kCells, 0.0);
  for (const auto& smp : sampler.sample(11, kN)) {
    const Vec3 d = (smp.point.position - Vec3(2, 0, 0)) / 0.5f;
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
    const int a = std::min(kCells - 1, int((d.z + 1) / 2 * kCells));
    const int b = std::min(kCells - 1, int((std::atan2(d.y, d.x) / (2 * M_PI) + 0.5) * kCells));
    count[std::size_t(a * kCells + b)] += 1;
  }
  double chi2 = 0;
  const double expected = double(kN) / (kCells * kCells);
  for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 103.4);
  // Next-event estimation's density of a point on the sphere equals the one it reports when it draws that point.
  const geometry::LightSampler lights(s);
  const geometry::Geometry g(s);
  Pcg32 rng(2, 2);
  const Vec3 from(0, 0.3f, 0.1f);
  for (int i = 0; i < 200; ++i) {
    const auto ls = lights.sample(from, rng);
    if (!(ls.pdf > 0)) continue;
    const auto hit = g.intersect({from, 0.0f, ls.direction});
    ASSERT_TRUE(hit.valid());
    if (std::fabs(hit.t - ls.distance) > 1e-4f) continue;  // drawn on the far side: hidden, no density by hitting
    EXPECT_NEAR(lights.pdf_triangle(g.surface(hit), from), ls.pdf, 1e-3f * ls.pdf);
  }
}

// Seen from outside, a sphere light is drawn by a direction uniform within the cone it subtends (none lands on its far,
// unlit side, as half of area sampling's did): χ² of those directions against the density the light sampler gives
// for a ray that meets the light (what multiple importance sampling weighs), from near and from further away.
TEST_F(Geometry, SphereLightsAreDrawnWithinTheirConeByTheDensityTheyReport) {
  const auto s = scene::load_scene(scene(R"(<shape type="sphere"><float name="radius" value="0.5"/>
      <point name="center" x="0.3" y="-0.2" z="0.4"/>
      <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)"));
  const geometry::Geometry g(s);
  const geometry::LightSampler lights(s);
  // 0.6 and 1 from the centre: cones of 56° and 30° (a narrower one slips between the χ² grid's quadrature nodes).
  for (const Vec3 from : {Vec3(0.3f, -0.2f, -0.2f), Vec3(0.3f + 0.6f, -0.2f + 0.8f, 0.4f)}) {
    const auto r = chi2_test(
        [&](Pcg32& rng) -> std::optional<Vec3> {
          const auto ls = lights.sample(from, rng);
          if (!(ls.pdf > 0)) return std::nullopt;
          EXPECT_GT(ls.radiance.x, 0.0f) << "a direction in the cone meets the lit side";
          return ls.direction;
        },
        [&](const Vec3& w) {
          const auto hit = g.intersect({from, 0.0f, w});
          return hit.valid() ? double(lights.pdf_triangle(g.surface(hit), from)) : 0.0;
        },
        400'000, 21);
    ASSERT_TRUE(r.problem.empty()) << r.problem;
    EXPECT_GT(r.p_value, 0.01) << "dof " << r.dof;
  }
}

}  // namespace
}  // namespace clr::test
