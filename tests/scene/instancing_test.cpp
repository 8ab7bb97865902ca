// Mitsuba's `cylinder` shape and instancing (`shapegroup` + `instance`).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::Vec3;

class Shapes : public SceneFiles {};

TEST_F(Shapes, CylinderIsAnOpenTubeFromP0ToP1) {
  const auto s = scene::load_scene(scene(R"(<shape type="cylinder">
    <point name="p0" value="1, 2, 3"/><point name="p1" value="1, 2, 7"/><float name="radius" value="0.5"/></shape>
    <shape type="cylinder"><transform name="to_world"><scale x="2"/></transform></shape>)"));
  ASSERT_TRUE(s.shapes[0].exact);  // exact (tests/geometry/exact_shapes_test.cpp)
  EXPECT_NEAR(s.shapes[0].area(), 2 * scene::kPi * 0.5 * 4, 1e-6 * 2 * scene::kPi * 0.5 * 4);  // no caps
  for (const float u : {0.0f, 0.3f, 0.7f})
    for (const float v : {0.0f, 0.5f, 1.0f}) {
      const Vec3 p = s.shapes[0].exact->position({u, v});
      const Vec3 radial = p - Vec3(1, 2, p.z);
      EXPECT_NEAR(glm::length(radial), 0.5f, 1e-5f);
      EXPECT_NEAR(glm::dot(s.shapes[0].exact->normal({u, v}), radial / 0.5f), 1.0f, 1e-5f);  // facing out
      EXPECT_NEAR(p.z, 3.0f + 4.0f * v, 1e-5f);
    }
  // An elliptic section is tessellated: its normals face out and the winding agrees with them.
  const auto& m = s.shapes[1].mesh;
  ASSERT_FALSE(m.triangles.empty());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3 radial(m.positions[i].x, m.positions[i].y, 0);
    EXPECT_GT(glm::dot(m.normals[i], radial), 0.0f);
    EXPECT_GE(m.positions[i].z, -1e-5f);
    EXPECT_LE(m.positions[i].z, 1.0f + 1e-5f);
  }
  const auto t = m.triangles[0];
  const Vec3 face = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
  EXPECT_GT(glm::dot(face, m.normals[t.x]), 0.0f);
}

TEST_F(Shapes, InstancesCopyTheirGroupUnderTheirTransform) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="instance" id="a"><ref id="pair"/>
      <transform name="to_world"><translate x="10"/></transform></shape>
    <shape type="shapegroup" id="pair">
      <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf></shape>
      <shape type="sphere"><float name="radius" value="0.5"/></shape>
    </shape>
    <shape type="instance"><ref name="shape" id="pair"/>
      <transform name="to_world"><scale value="2"/></transform></shape>)"));
  ASSERT_EQ(s.shapes.size(), 4u);                             // the group itself is not rendered
  EXPECT_NEAR(s.shapes[0].mesh.positions[0].x, 9.0f, 1e-6f);  // (-1, -1, 0) translated
  EXPECT_NEAR(s.shapes[2].mesh.positions[0].x, -2.0f, 1e-6f);
  EXPECT_NEAR(s.shapes[3].area(), 4 * scene::kPi, 1e-5);  // radius 0.5 scaled by 2, exact
  EXPECT_EQ(s.shapes[0].material, s.shapes[2].material);  // the instances share the group's BSDF
  EXPECT_EQ(s.shapes[0].id.rfind("a/", 0), 0u);
  auto refused = [&](const std::string& body) -> std::string {
    try {
      scene::load_scene(scene(body));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_THAT(refused(R"(<shape type="shapegroup" id="g"><shape type="rectangle">
    <emitter type="area"/></shape></shape>)"),
              ::testing::HasSubstr("cannot emit"));
  EXPECT_THAT(refused(R"(<bsdf type="diffuse" id="d"/><shape type="instance"><ref id="d"/></shape>)"),
              ::testing::HasSubstr("no shapegroup"));
  EXPECT_THAT(refused(R"(<shape type="instance"/>)"), ::testing::HasSubstr("needs a <ref>"));
}

}  // namespace
}  // namespace clr::test
