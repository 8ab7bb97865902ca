// Mitsuba's cylinder and disk kept exact (scene/exact_shape.hpp), as the sphere is (geometry_test.cpp): hits at the
// analytic distance, Mitsuba 3's uv, normals and tangents, area-uniform sampling and the light density that next-event
// estimation reports. The conventions were read off Mitsuba 3.9.1's own intersections (scalar_rgb: si.uv, si.n,
// si.dp_du, si.dp_dv for disks and cylinders under mirrors and stretches).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "geometry/light_sampler.hpp"
#include "geometry/surface_sampler.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::ExactShape;
using scene::Vec2;
using scene::Vec3;
using Kind = ExactShape::Kind;

class ExactShapes : public SceneFiles {};

// A to_world that every kind keeps exact: a rotation about a skew axis, a uniform scale and an offset.
glm::mat4 placement() {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), Vec3(3, -2, 5));
  m = glm::rotate(m, 0.7f, glm::normalize(Vec3(1, 2, 3)));
  return glm::scale(m, Vec3(1.5f));
}

// For each kind, under a placement, a mirror and (disk only) a shear: the point at uv comes back as uv; ∂p/∂u and
// ∂p/∂v are the position's finite differences; the normal is square to both and faces where the inverse transpose
// takes the local normal (outwards; a mirror keeps a tube's and a sphere's outwards, and turns a disk's as Mitsuba's).
TEST_F(ExactShapes, UvTangentsAndNormalsAreThoseOfTheParametrisation) {
  const glm::mat4 mirror = glm::scale(placement(), Vec3(1, 1, -1));
  const glm::mat4 shear = placement() * glm::mat4(glm::vec4(2, 0, 0, 0), glm::vec4(0.6f, 0.5f, 0, 0),
                                                  glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1));
  struct Case {
    Kind kind;
    glm::mat4 to_world;
  };
  for (const Case& c : {Case{Kind::sphere, placement()}, Case{Kind::sphere, mirror}, Case{Kind::cylinder, placement()},
                        Case{Kind::cylinder, mirror}, Case{Kind::disk, placement()}, Case{Kind::disk, mirror},
                        Case{Kind::disk, shear}}) {
    const auto s = ExactShape::from(c.kind, c.to_world, false);
    ASSERT_TRUE(s) << int(c.kind);
    const auto flipped = ExactShape::from(c.kind, c.to_world, true);
    Pcg32 rng(int(c.kind) + 1, 3);
    for (int i = 0; i < 200; ++i) {
      const Vec2 uv(0.05f + 0.9f * rng.next_float(), 0.05f + 0.9f * rng.next_float());
      const Vec3 p = s->position(uv);
      const Vec2 back = s->uv(glm::dvec3(p) - glm::dvec3(s->origin));
      ASSERT_NEAR(back.x, uv.x, 2e-5f) << int(c.kind) << " " << i;
      ASSERT_NEAR(back.y, uv.y, 2e-5f) << int(c.kind) << " " << i;
      Vec3 dpdu, dpdv;
      s->tangents(uv, dpdu, dpdv);
      constexpr float h = 1e-3f;
      const Vec3 fu = (s->position(uv + Vec2(h, 0)) - s->position(uv - Vec2(h, 0))) / (2 * h);
      const Vec3 fv = (s->position(uv + Vec2(0, h)) - s->position(uv - Vec2(0, h))) / (2 * h);
      ASSERT_LT(glm::length(dpdu - fu), 2e-3f * glm::length(dpdu)) << int(c.kind) << " " << i;
      ASSERT_LT(glm::length(dpdv - fv), 2e-3f * glm::length(dpdv)) << int(c.kind) << " " << i;
      const Vec3 n = s->normal(uv);
      ASSERT_NEAR(glm::length(n), 1.0f, 1e-6f);
      ASSERT_LT(std::fabs(glm::dot(n, dpdu)), 1e-4f * glm::length(dpdu));
      ASSERT_LT(std::fabs(glm::dot(n, dpdv)), 1e-4f * glm::length(dpdv));
      const glm::mat3 normal_map = glm::transpose(glm::inverse(glm::mat3(c.to_world)));
      const Vec3 local = c.kind == Kind::disk ? Vec3(0, 0, 1)
                         : c.kind == Kind::cylinder
                             ? Vec3(std::cos(2 * scene::kPi * uv.x), std::sin(2 * scene::kPi * uv.x), 0)
                             : glm::inverse(glm::mat3(c.to_world)) * (p - s->origin);
      ASSERT_GT(glm::dot(n, normal_map * local), 0.0f) << int(c.kind) << " " << i;
      ASSERT_EQ(flipped->normal(uv), -n);
    }
  }
  // The mirrored disk faces −z in its own frame as Mitsuba's does (its si.n under scale z = −1 is (0, 0, −1)).
  EXPECT_NEAR(ExactShape::from(Kind::disk, glm::scale(glm::mat4(1.0f), Vec3(1, 1, -1)), false)->normal({0.5f, 0.2f}).z,
              -1.0f, 1e-6f);
}

// What stays exact and what is tessellated: a stretched section makes an elliptic tube (Mitsuba warns, intersects
// the ellipse and reports the area of a round tube of the x radius: 4π where the tube's is 9.69); a stretched disk is
// an ellipse whose area density is still constant, so it stays exact. Areas are the exact ones.
TEST_F(ExactShapes, KeptExactWhereTheShapeStaysWhatMitsubaModels) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="cylinder"><point name="p0" x="1" y="2" z="3"/><point name="p1" x="1" y="2" z="5"/>
      <float name="radius" value="0.5"/></shape>
    <shape type="cylinder"><transform name="to_world"><scale x="2"/></transform></shape>
    <shape type="disk"><transform name="to_world"><scale x="2" y="0.5"/><rotate x="1" angle="30"/></transform></shape>
    <shape type="shapegroup" id="g"><shape type="cylinder"/><shape type="disk"/></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale value="3"/></transform></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale y="3"/></transform></shape>)"));
  ASSERT_EQ(s.shapes.size(), 7u);
  ASSERT_TRUE(s.shapes[0].exact);
  EXPECT_NEAR(s.shapes[0].area(), 2 * M_PI, 1e-5);  // 2π·r·length
  EXPECT_FALSE(s.shapes[1].exact);
  EXPECT_NEAR(s.shapes[1].area(), 9.6884, 1e-3);  // the ellipse's perimeter (semi-axes 2 and 1) × 1
  ASSERT_TRUE(s.shapes[2].exact);
  EXPECT_NEAR(s.shapes[2].area(), M_PI, 1e-5);  // π·2·0.5
  ASSERT_TRUE(s.shapes[3].exact);
  EXPECT_NEAR(s.shapes[3].area(), 2 * M_PI * 9, 1e-4);
  ASSERT_TRUE(s.shapes[4].exact);
  EXPECT_NEAR(s.shapes[4].area(), M_PI * 9, 1e-4);
  EXPECT_FALSE(s.shapes[5].exact) << "a stretch across the axis tessellates that copy only";
  ASSERT_TRUE(s.shapes[6].exact);
  EXPECT_NEAR(s.shapes[6].area(), M_PI * 3, 1e-4);
  std::size_t triangles = 0;
  for (const std::size_t i : {0, 2, 3, 4, 6}) triangles += s.shapes[i].mesh.triangles.size();
  EXPECT_EQ(triangles, 0u);
}

// Scales whose product underflows a float determinant (1e-10 in the group, 1e-10 in the instance: 1e-60) stay exact
// shapes of the right size, not a refusal or a crash.
TEST_F(ExactShapes, TinyNestedScalesStayExact) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="shapegroup" id="g">
      <shape type="disk"><transform name="to_world"><scale value="1e-10"/></transform></shape>
      <shape type="cylinder"><transform name="to_world"><scale value="1e-10"/></transform></shape></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale value="1e-10"/></transform></shape>)"));
  ASSERT_EQ(s.shapes.size(), 2u);
  ASSERT_TRUE(s.shapes[0].exact && s.shapes[1].exact);
  EXPECT_NEAR(s.shapes[0].area() / (M_PI * 1e-40), 1.0, 1e-5);
  EXPECT_NEAR(s.shapes[1].area() / (2 * M_PI * 1e-40), 1.0, 1e-5);
}

// Rays meet the tube at the analytic distance from outside and (its inside being open) from inside, miss it past its
// ends and along its axis, and hit a stretched disk inside its ellipse only; uv as Mitsuba's: the tube's (φ/2π, z)
// from Mitsuba's frame of the axis, the disk's (r, φ/2π).
TEST_F(ExactShapes, CylindersAndDisksAreHitExactly) {
  for (const double scale : {1e-3, 1.0, 1e3}) {
    const auto f = [&](double v) { return std::to_string(v * scale); };
    const auto s = scene::load_scene(scene(R"(<shape type="cylinder"><point name="p0" x=")" + f(1) + R"(" y=")" + f(2) +
                                           R"(" z=")" + f(3) + R"("/><point name="p1" x=")" + f(1) + R"(" y=")" + f(2) +
                                           R"(" z=")" + f(5) + R"("/><float name="radius" value=")" + f(0.5) +
                                           R"("/></shape>
      <shape type="disk"><transform name="to_world"><scale x=")" +
                                           f(2) + R"(" y=")" + f(0.5) + R"("/>
        <translate x=")" + f(10) + R"("/></transform></shape>)"));
    ASSERT_TRUE(s.shapes[0].exact && s.shapes[1].exact);
    const geometry::Geometry g(s);
    const float k = float(scale), r = 0.5f * k;
    const Vec3 axis0 = Vec3(1, 2, 3) * k;
    Pcg32 rng(7, 1);
    for (int i = 0; i < 1000; ++i) {
      // From 3 radii out at a random height (within or past the ends) towards a random point of the axis' segment.
      const float phi = 2 * scene::kPi * rng.next_float(), z_from = (-1 + 6 * rng.next_float()) * k;
      const Vec3 from = axis0 + Vec3(3 * r * std::cos(phi), 3 * r * std::sin(phi), z_from);
      const Vec3 to = axis0 + Vec3(0.3f * r * (rng.next_float() - 0.5f), 0.3f * r * (rng.next_float() - 0.5f),
                                   2 * k * rng.next_float());
      const Vec3 dir = glm::normalize(to - from);
      const glm::dvec2 o(from.x - axis0.x, from.y - axis0.y), d(dir.x, dir.y);
      const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - double(r) * r;
      const double t_near = (-b - std::sqrt(b * b - a * c)) / a, z = double(from.z - axis0.z) + t_near * dir.z;
      const auto hit = g.intersect({from, 0.0f, dir});
      if (z < 0 || z > 2 * k) {
        // Past the ends the near side is missed; the far side may still be met, from inside.
        if (hit.valid()) {
          ASSERT_GT(hit.t, t_near) << scale << " " << i;
        }
        continue;
      }
      ASSERT_TRUE(hit.valid()) << scale << " " << i;
      ASSERT_NEAR(hit.t, t_near, 1e-5 * k) << scale << " " << i;
      const auto p = g.surface(hit);
      const Vec3 radial = p.position - axis0;
      double phi_hit = std::atan2(radial.y, radial.x);
      if (phi_hit < 0) phi_hit += 2 * M_PI;
      ASSERT_NEAR(p.at.uv.x, phi_hit / (2 * M_PI), 1e-5) << scale << " " << i;
      ASSERT_NEAR(p.at.uv.y, radial.z / (2 * k), 1e-5) << scale << " " << i;
      ASSERT_NEAR(glm::length(p.geometric_normal - glm::normalize(Vec3(radial.x, radial.y, 0))), 0.0f, 1e-4f);
      // On through the open tube: the far side from inside, its normal facing away from the ray.
      const auto far = g.intersect({p.spawn_origin(dir), 0.0f, dir});
      if (far.valid() && far.shape == 0) {
        ASSERT_GT(glm::dot(g.surface(far).geometric_normal, dir), 0.0f);
      }
    }
    // Down the axis from inside, and parallel to it outside: no crossing.
    EXPECT_FALSE(g.intersect({axis0 + Vec3(0, 0, k), 0.0f, Vec3(0, 0, 1)}).valid());
    EXPECT_FALSE(g.intersect({axis0 + Vec3(2 * r, 0, -k), 0.0f, Vec3(0, 0, 1)}).valid());
    // The disk: an ellipse of semi-axes 2 and 0.5 about x = 10, hit from above inside it, missed outside.
    for (int i = 0; i < 1000; ++i) {
      const float x = 2.4f * (rng.next_float() - 0.5f) * 2, y = 0.6f * (rng.next_float() - 0.5f) * 2;
      const Vec3 from = Vec3(10 + x, y, 1) * k;
      const auto hit = g.intersect({from, 0.0f, Vec3(0, 0, -1)});
      const float lx = x / 2, ly = y / 0.5f, rl = std::sqrt(lx * lx + ly * ly);
      if (std::fabs(rl - 1) < 1e-4f) continue;
      ASSERT_EQ(hit.valid(), rl < 1) << scale << " " << i;
      if (!hit.valid()) continue;
      ASSERT_NEAR(hit.t, k, 1e-6f * k);
      const auto p = g.surface(hit);
      double phi = std::atan2(ly, lx);
      if (phi < 0) phi += 2 * M_PI;
      ASSERT_NEAR(p.at.uv.x, rl, 1e-5f);
      ASSERT_NEAR(p.at.uv.y, phi / (2 * M_PI), 2e-5 / rl);
      ASSERT_NEAR(p.geometric_normal.z, 1.0f, 1e-6f);
    }
  }
}

// Points are drawn uniformly by area (χ² over cells of equal area: (φ, z) on the tube, (r², φ) on the disk; 63
// degrees of freedom, whose 99.9 % quantile is 103.4), and next-event estimation's density of a point it draws equals
// the one it gives that point when a ray meets it.
TEST_F(ExactShapes, SamplesAreUniformByAreaAndTheLightDensityMatches) {
  for (const std::string shape :
       {R"(<shape type="cylinder"><transform name="to_world"><rotate y="1" angle="30"/><scale value="0.5"/>
          <translate x="2"/></transform>)",
        R"(<shape type="disk"><transform name="to_world"><scale x="2" y="0.5"/><rotate y="1" angle="30"/>
          <translate x="2"/></transform>)"}) {
    const auto s =
        scene::load_scene(scene(shape + R"(<emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"));
    const ExactShape& e = *s.shapes[0].exact;
    const geometry::SurfaceSampler sampler(s);
    EXPECT_NEAR(sampler.total_area(), e.kind == Kind::cylinder ? M_PI / 2 : M_PI, 1e-5);
    constexpr int kCells = 8;
    constexpr std::size_t kN = 128000;
    std::vector<double> count(kCells * kCells, 0.0);
    const glm::dmat3 to_local = glm::inverse(glm::dmat3(e.linear));
    for (const auto& smp : sampler.sample(11, kN)) {
      const glm::dvec3 l = to_local * (glm::dvec3(smp.point.position) - glm::dvec3(e.origin));
      const double phi = std::atan2(l.y, l.x) / (2 * M_PI) + 0.5;
      const double other = e.kind == Kind::cylinder ? l.z : l.x * l.x + l.y * l.y;
      ASSERT_NEAR(e.kind == Kind::cylinder ? l.x * l.x + l.y * l.y : l.z, e.kind == Kind::cylinder ? 1.0 : 0.0, 1e-5);
      const int a = std::min(kCells - 1, int(other * kCells)), b = std::min(kCells - 1, int(phi * kCells));
      count[std::size_t(a * kCells + b)] += 1;
    }
    double chi2 = 0;
    const double expected = double(kN) / (kCells * kCells);
    for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 103.4) << shape;
    const geometry::LightSampler lights(s);
    const geometry::Geometry g(s);
    Pcg32 rng(2, 2);
    int checked = 0;
    for (const Vec3 from : {Vec3(0, 0.3f, 0.1f), Vec3(2, 0.1f, 1.5f), Vec3(2, -0.1f, -1.5f)})
      for (int i = 0; i < 200; ++i) {
        const auto ls = lights.sample(from, rng);
        if (!(ls.pdf > 0)) continue;
        const auto hit = g.intersect({from, 0.0f, ls.direction});
        ASSERT_TRUE(hit.valid());
        if (std::fabs(hit.t - ls.distance) > 1e-4f) continue;  // drawn where a nearer part hides it
        const auto p = g.surface(hit);
        // At grazing angles the density's 1/cos turns the float error of two normals into more than 1e-3.
        if (std::fabs(glm::dot(p.geometric_normal, ls.direction)) < 0.05f) continue;
        EXPECT_NEAR(lights.pdf_triangle(p, from), ls.pdf, 1e-3f * ls.pdf);
        ++checked;
      }
    EXPECT_GT(checked, 100) << shape;
  }
}

}  // namespace
}  // namespace clr::test
