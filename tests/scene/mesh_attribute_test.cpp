// Mitsuba 3's mesh attributes: PLY properties read as vertex_/face_ attributes by its naming rules, the
// `mesh_attribute` texture's value at a hit (face attributes constant over a triangle, vertex attributes
// interpolated), and the loader's checks: an attribute a material reads must be on the shape's mesh.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"
#include "scene/shapes/ply_attributes.hpp"

namespace clr::test {
namespace {

using scene::Rgb;
using scene::Vec2;
using ::testing::HasSubstr;

class MeshAttributes : public SceneFiles {};

void expect_rgb(const Rgb& a, const Rgb& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

const scene::MeshAttribute& attribute(const scene::Mesh& m, const std::string& name) {
  const auto* a = m.attribute(name);
  if (!a) throw std::runtime_error("no attribute " + name);
  return *a;
}

// A unit square of two triangles (a quad, fanned) plus one more triangle; uchar colours and an alpha per vertex, a
// 1-channel vertex attribute, and per face a 3-channel colour and a 1-channel weight.
const char* kPly = R"(ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
property float height_0
property float u
property float v
element face 2
property list uchar int vertex_indices
property float color_0
property float color_1
property float color_2
property float weight_0
end_header
0 0 0 255 0 0 1 0 0
1 0 0 0 255 0 2 1 0
1 1 0 0 0 255 3 1 1
0 1 0 10 20 30 4 0 1
2 0 0 0 0 0 5 0 0
4 0 1 2 3 0.1 0.2 0.3 0.25
3 1 4 2 0.4 0.5 0.6 0.75
)";

TEST_F(MeshAttributes, PlyPropertiesBecomeVertexAndFaceAttributes) {
  const auto m = scene::load_ply(write("a.ply", kPly));
  ASSERT_EQ(m.triangles.size(), 3u);  // the quad fanned into two
  ASSERT_EQ(m.attributes.size(), 4u);
  const auto& color = attribute(m, "vertex_color");
  EXPECT_EQ(color.channels, 3);
  // As stored: Mitsuba 3 neither normalises nor gamma-decodes integer colours.
  EXPECT_EQ(color.values, (std::vector<float>{255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 0, 0, 0}));
  const auto& height = attribute(m, "vertex_height");
  EXPECT_EQ(height.channels, 1);
  EXPECT_EQ(height.values, (std::vector<float>{1, 2, 3, 4, 5}));
  // The quad's two triangles share its face values.
  const auto& face_color = attribute(m, "face_color");
  EXPECT_EQ(face_color.channels, 3);
  EXPECT_EQ(face_color.values, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}));
  EXPECT_EQ(attribute(m, "face_weight").values, (std::vector<float>{0.25f, 0.25f, 0.75f}));
  EXPECT_TRUE(attribute(m, "face_weight").per_face());
  EXPECT_FALSE(color.per_face());
  EXPECT_NO_THROW(m.validate("a.ply"));
}

TEST_F(MeshAttributes, MeshesWithoutExtraPropertiesHaveNone) {
  const auto m = scene::load_ply(write("plain.ply", R"(ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
property float nx
property float ny
property float nz
element face 1
property list uchar int vertex_indices
end_header
0 0 0 0 0 1
1 0 0 0 0 1
0 1 0 0 0 1
3 0 1 2
)"));
  EXPECT_TRUE(m.attributes.empty());
}

// Mitsuba's naming rules (probed against Mitsuba 3.9.1): names are what its ply plugin produces for the same
// header.
TEST(PlyAttributeNames, FollowMitsubasRules) {
  auto names = [](const std::vector<std::string>& properties) {
    std::vector<std::string> out;
    for (const auto& a : scene::ply_attributes("vertex", properties)) {
      std::string channels;
      for (const std::size_t p : a.properties) channels += std::to_string(p);
      out.push_back(a.name + ":" + channels);
    }
    return out;
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(names({"r", "g", "b"}), (V{"vertex_color:012"}));
  EXPECT_EQ(names({"red", "green", "blue", "alpha"}), (V{"vertex_color:0123"}));  // 4 channels: read, not evaluable
  EXPECT_EQ(names({"r", "g"}), V{});                                              // no colour without blue
  EXPECT_EQ(names({"q_r", "q_g", "q_b"}), (V{"vertex_q_color:012"}));
  EXPECT_EQ(names({"n_x", "n_y", "n_z"}), (V{"vertex_n:012"}));
  EXPECT_EQ(names({"c_1", "c_2", "c_3"}), (V{"vertex_c:012"}));
  EXPECT_EQ(names({"w_0"}), (V{"vertex_w:0"}));
  EXPECT_EQ(names({"a_x", "a_y", "a_z", "a_w"}), V{});  // 4 channels
  EXPECT_EQ(names({"t_x", "t_y"}), V{});                // 2 channels
  EXPECT_EQ(names({"d_x", "d_z"}), V{});                // a broken sequence
  EXPECT_EQ(names({"plain", "long_xy", "k_q"}), V{});   // no postfix, a long one, one that starts no sequence
  EXPECT_EQ(names({"p_0", "o_0", "p_1"}), (V{"vertex_p:0", "vertex_o:1"}));  // a prefix names one attribute
  EXPECT_EQ(names({"", "e_0", ""}), (V{"vertex_e:1"}));                      // empty: not an attribute
}

scene::Mesh triangle_with_attributes() {
  scene::Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  m.attributes = {{"vertex_color", 3, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}},
                  {"vertex_height", 1, {0, 10, 20, 30}},
                  {"face_weight", 1, {0.25f, 0.75f}},
                  {"face_color", 3, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}}};
  return m;
}

TEST(MeshAttributeTexture, FaceAttributesAreConstantOverATriangle) {
  const auto m = triangle_with_attributes();
  const auto weight = scene::Texture::mesh_attribute("face_weight", 1.0f, "w");
  const auto color = scene::Texture::mesh_attribute("face_color", 2.0f, "c");
  for (const Vec2 b : {Vec2(0, 0), Vec2(0.3f, 0.6f), Vec2(1, 0)}) {
    expect_rgb(weight.eval(m.texture_point(0, b)), Rgb(0.25f));  // one channel replicated
    expect_rgb(weight.eval(m.texture_point(1, b)), Rgb(0.75f));
    expect_rgb(color.eval(m.texture_point(1, b)), Rgb(0.8f, 1.0f, 1.2f));  // times the scale
  }
}

TEST(MeshAttributeTexture, VertexAttributesInterpolateWithBarycentrics) {
  const auto m = triangle_with_attributes();
  const auto color = scene::Texture::mesh_attribute("vertex_color", 1.0f, "c");
  const auto height = scene::Texture::mesh_attribute("vertex_height", 0.5f, "h");
  // Triangle 0 at b = (0.2, 0.3): weights 0.5, 0.2, 0.3 of vertices 0, 1, 2.
  expect_rgb(color.eval(m.texture_point(0, Vec2(0.2f, 0.3f))), Rgb(0.5f, 0.2f, 0.3f));
  expect_rgb(height.eval(m.texture_point(0, Vec2(0.2f, 0.3f))), Rgb(0.5f * (0.2f * 10 + 0.3f * 20)));
  // Triangle 1 (vertices 1, 3, 2) at b = (0.5, 0.25): 0.25·v1 + 0.5·v3 + 0.25·v2.
  expect_rgb(color.eval(m.texture_point(1, Vec2(0.5f, 0.25f))), Rgb(0.5f, 0.75f, 0.75f));
  expect_rgb(height.eval(m.texture_point(1, Vec2(0.5f, 0.25f))), Rgb(0.5f * (2.5f + 15 + 5)));
  // A bare uv names no mesh: black.
  expect_rgb(color.eval(Vec2(0.5f)), Rgb(0.0f));
}

// The ply of kPly under a material reading `attribute` (a blendbsdf weight and a diffuse reflectance).
std::string shape_reading(const std::string& weight, const std::string& reflectance) {
  return R"(<texture type="mesh_attribute" id="weight_tex"><string name="name" value=")" + weight +
         R"("/></texture>
    <shape type="ply" id="quad"><string name="filename" value="a.ply"/>
      <bsdf type="blendbsdf"><ref name="weight" id="weight_tex"/>
        <bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
          <string name="name" value=")" +
         reflectance + R"("/><float name="scale" value="0.5"/></texture></bsdf>
        <bsdf type="diffuse"/>
      </bsdf>
    </shape>)";
}

TEST_F(MeshAttributes, ShapesKeepTheAttributesTheirMaterialsRead) {
  write("a.ply", kPly);
  const auto s = scene::load_scene(scene(shape_reading("face_weight", "vertex_color")));
  const auto& mesh = s.shapes.at(0).mesh;
  ASSERT_EQ(mesh.attributes.size(), 2u);
  EXPECT_NE(mesh.attribute("face_weight"), nullptr);
  EXPECT_NE(mesh.attribute("vertex_color"), nullptr);

  // A ray down onto the first triangle finds the face's weight and the interpolated vertex colour.
  const geometry::Geometry g(s);
  const auto hit = g.intersect({{0.75f, 0.25f, 1}, 0, {0, 0, -1}});
  ASSERT_TRUE(hit.valid());
  const auto p = g.surface(hit);
  EXPECT_EQ(p.at.mesh, &mesh);
  EXPECT_EQ(p.at.prim, 0u);
  const auto reflectance = scene::Texture::mesh_attribute("vertex_color", 0.5f, "r");
  // At (0.75, 0.25): vertex 0 weight 0.25, vertex 1 weight 0.5, vertex 2 weight 0.25 (colours red, green, blue).
  expect_rgb(reflectance.eval(p.at), 0.5f * Rgb(0.25f * 255, 0.5f * 255, 0.25f * 255), 1e-3f);
}

TEST_F(MeshAttributes, AnAreaEmittersRadianceMayBeAnAttribute) {
  write("a.ply", kPly);
  const auto s = scene::load_scene(scene(R"(<shape type="ply"><string name="filename" value="a.ply"/>
      <emitter type="area"><texture type="mesh_attribute" name="radiance">
        <string name="name" value="face_weight"/><float name="scale" value="4"/></texture></emitter></shape>)"));
  ASSERT_TRUE(s.shapes.at(0).radiance_texture.has_value());
  ASSERT_EQ(s.shapes[0].mesh.attributes.size(), 1u);
  const geometry::Geometry g(s);
  const auto p = g.surface(g.intersect({{1.5f, 0.25f, 1}, 0, {0, 0, -1}}));  // the third triangle, weight 0.75
  EXPECT_EQ(p.at.prim, 2u);
  expect_rgb(geometry::emitted(s, p, p.frame.n), Rgb(3.0f));
}

TEST(MeshAttributeTexture, CreaseNormalsCarryVertexAttributesToEveryCorner) {
  auto m = triangle_with_attributes();
  m.compute_crease_normals(30.0f);
  ASSERT_EQ(m.positions.size(), 6u);  // every corner its own vertex
  ASSERT_NO_THROW(m.validate("creased"));
  const auto height = scene::Texture::mesh_attribute("vertex_height", 1.0f, "h");
  const auto weight = scene::Texture::mesh_attribute("face_weight", 1.0f, "w");
  // Triangle 1 was vertices 1, 3, 2 (heights 10, 30, 20): the same values at the same barycentrics.
  expect_rgb(height.eval(m.texture_point(1, Vec2(0.5f, 0.25f))), Rgb(0.25f * 10 + 0.5f * 30 + 0.25f * 20));
  expect_rgb(weight.eval(m.texture_point(1, Vec2(0.5f, 0.25f))), Rgb(0.75f));
}

TEST_F(MeshAttributes, AMissingAttributeNamesTheTextureTheAttributeAndTheShape) {
  write("a.ply", kPly);
  try {
    scene::load_scene(scene(shape_reading("face_missing", "vertex_color")));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mesh_attribute texture 'weight_tex' reads attribute 'face_missing'"));
    EXPECT_THAT(e.what(), HasSubstr("shape 'quad' does not have"));
    EXPECT_THAT(e.what(), HasSubstr("it has vertex_color, vertex_height, face_color, face_weight"));
  }
}

// A parameter read as a number (Texture::eval_1) takes a 1-channel attribute; Mitsuba fails mid-render on a
// 3-channel one ("requested but had size 3"), here the scene is refused naming the parameter. The same attribute
// read as a colour is kept.
TEST_F(MeshAttributes, ANumberReadsOnlyAOneChannelAttribute) {
  write("a.ply", kPly);
  try {
    scene::load_scene(scene(shape_reading("face_color", "face_color")));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("reads attribute 'face_color' of shape 'quad' as the number 'weight'"));
    EXPECT_THAT(e.what(), HasSubstr("it has 3 channels"));
  }
  EXPECT_THROW(scene::load_scene(scene(R"(<shape type="ply"><string name="filename" value="a.ply"/>
      <bsdf type="principled"><texture type="mesh_attribute" name="metallic">
        <string name="name" value="vertex_color"/></texture></bsdf></shape>)")),
               InputError);
  const auto s = scene::load_scene(scene(R"(<shape type="ply"><string name="filename" value="a.ply"/>
      <bsdf type="roughconductor"><texture type="mesh_attribute" name="alpha">
        <string name="name" value="face_weight"/></texture></bsdf></shape>)"));
  EXPECT_NE(s.shapes.at(0).mesh.attribute("face_weight"), nullptr);
}

TEST_F(MeshAttributes, BadNamesAndShapesWithoutAttributesAreRefused) {
  write("a.ply", kPly);
  EXPECT_THROW(scene::load_scene(scene(shape_reading("weight", "vertex_color"))), InputError);  // no prefix
  try {
    scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="diffuse">
      <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture>
      </bsdf></shape>)"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("it has no attributes"));
  }
  EXPECT_THROW(scene::load_scene(scene(R"(<emitter type="spot">
      <texture type="mesh_attribute" name="texture"><string name="name" value="vertex_color"/></texture>
      </emitter>)")),
               InputError);
}

}  // namespace
}  // namespace clr::test
