// The Mitsuba loader, tag by tag: values, version upgrade, defaults, includes, references, transforms, shapes,
// materials, textures, emitters and the sensor.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstring>

#include "common/error.hpp"
#include "image/image.hpp"
#include "scene/bsdfs.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"
#include "scene/xml/xml_source.hpp"

namespace clr::test {
namespace {

using scene::Rgb;
using scene::Vec2;
using scene::Vec3;

class Loader : public SceneFiles {};

void expect_vec(const Vec3& a, const Vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST_F(Loader, OldVersionsUseCamelCaseNames) {
  const auto s = scene::load_scene(scene(R"(
    <sensor type="perspective">
      <float name="fov" value="30"/> <string name="fovAxis" value="y"/> <float name="nearClip" value="0.5"/>
      <transform name="toWorld"><translate x="1" y="2" z="3"/></transform>
      <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film>
    </sensor>
    <shape type="rectangle">
      <bsdf type="plastic"><rgb name="diffuseReflectance" value="0.3, 0.2, 0.1"/><float name="intIOR" value="1.6"/></bsdf>
      <boolean name="flipNormals" value="true"/>
    </shape>)",
                                         "0.5.0"));
  EXPECT_EQ(s.camera.fov_axis, scene::Camera::FovAxis::y);
  EXPECT_FLOAT_EQ(s.camera.near_clip, 0.5f);
  EXPECT_EQ(s.camera.width, 64);
  expect_vec(Vec3(s.camera.to_world[3]), Vec3(1, 2, 3));
  expect_vec(s.bsdf(s.shapes[0]).albedo(Vec2(0)), Vec3(0.3f, 0.2f, 0.1f));
  expect_vec(s.shapes[0].mesh.normals[0], Vec3(0, 0, -1));
  EXPECT_EQ(scene::xml::snake_case("intIOR"), "int_ior");
  EXPECT_EQ(scene::xml::snake_case("toWorld"), "to_world");
  EXPECT_EQ(scene::xml::snake_case("specularReflectance"), "specular_reflectance");
}

TEST_F(Loader, DefaultsAndParametersSubstitute) {
  const auto file = scene(R"(
    <default name="albedo" value="0.25"/>
    <default name="res" value="16"/>
    <sensor type="perspective"><float name="fov" value="40"/>
      <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
    </sensor>
    <shape type="rectangle"><bsdf type="diffuse"><float name="reflectance" value="$albedo"/></bsdf></shape>)");
  auto s = scene::load_scene(file);
  EXPECT_EQ(s.camera.width, 16);
  EXPECT_FLOAT_EQ(s.bsdf(s.shapes[0]).albedo(Vec2(0)).x, 0.25f);
  s = scene::load_scene(file, {{"albedo", "0.75"}});  // like mitsuba -D: the caller wins over <default>
  EXPECT_FLOAT_EQ(s.bsdf(s.shapes[0]).albedo(Vec2(0)).x, 0.75f);
}

TEST_F(Loader, ColourTags) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><bsdf type="diffuse"><srgb name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="diffuse"><spectrum name="reflectance" value="0.3"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.1 0.2 0.3"/></bsdf></shape>)"));
  EXPECT_NEAR(s.bsdf(s.shapes[0]).albedo(Vec2(0)).x, 0.2140f, 1e-4f);  // sRGB-decoded
  EXPECT_FLOAT_EQ(s.bsdf(s.shapes[1]).albedo(Vec2(0)).y, 0.3f);
  expect_vec(s.bsdf(s.shapes[2]).albedo(Vec2(0)), Vec3(0.1f, 0.2f, 0.3f));  // spaces separate like commas
  EXPECT_THROW(scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="diffuse">
    <spectrum name="reflectance" value="400:0.1, 300:0.2"/></bsdf></shape>)")),
               InputError);  // wavelengths must increase
}

TEST_F(Loader, IncludesShareIdsAndResolvePathsFromTheirOwnFile) {
  std::filesystem::create_directories(dir_ / "parts");
  write("parts/materials.xml", R"(<scene version="3.0.0"><bsdf type="diffuse" id="red">
    <rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf></scene>)");
  const auto s = scene::load_scene(scene(R"(<include filename="parts/materials.xml"/>
    <shape type="cube"><ref id="red"/></shape><shape type="rectangle"><ref id="red"/></shape>)"));
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].material, s.shapes[1].material);  // one BSDF, one material id
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_FLOAT_EQ(s.bsdf(s.shapes[0]).albedo(Vec2(0)).x, 0.8f);
}

TEST_F(Loader, TransformsApplyInDocumentOrder) {
  const auto s = scene::load_scene(scene(R"(<shape type="rectangle"><transform name="to_world">
      <scale x="2"/> <rotate z="1" angle="90"/> <translate x="10"/>
    </transform></shape>
    <shape type="rectangle"><transform name="to_world">
      <matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>
    </transform></shape>
    <shape type="rectangle"><transform name="to_world">
      <lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/>
    </transform></shape>)"));
  // (1, 1, 0) → scale (2, 1, 0) → rotate 90° about z (−1, 2, 0) → translate (9, 2, 0).
  expect_vec(s.shapes[0].mesh.positions[2], Vec3(9, 2, 0));
  expect_vec(s.shapes[1].mesh.positions[0], Vec3(4, 5, 7));
  // lookat maps +z to the view direction and +x to the left (up × dir).
  expect_vec(s.shapes[2].mesh.normals[0], Vec3(0, 0, -1));
  expect_vec(s.shapes[2].mesh.positions[1], Vec3(-1, -1, 0));
}

// A rotation axis that is not of unit length: Mitsuba 2 and 3 put it into Rodrigues' formula as given (the rotation
// then also scales along the axis and across it), Mitsuba 0.6 normalised it; each scene version reads as its own.
TEST_F(Loader, ARotationAxisCountsAsItsSceneVersionReadsIt) {
  const std::string shape = R"(<shape type="rectangle"><transform name="to_world">
      <rotate z="2" angle="90"/></transform></shape>)";
  // (1, 1, 0): c = 0, s = 1, so R·p = (a·p)·a + a × p = (0, 0, 2) × (1, 1, 0) = (−2, 2, 0).
  expect_vec(scene::load_scene(scene(shape)).shapes[0].mesh.positions[2], Vec3(-2, 2, 0));
  expect_vec(scene::load_scene(scene(shape, "0.6.0", "old.xml")).shapes[0].mesh.positions[2], Vec3(-1, 1, 0));
}

TEST_F(Loader, AnalyticShapesHaveTheirAreasAndNormals) {
  const auto s = scene::load_scene(scene(R"(<shape type="rectangle"/> <shape type="cube"/> <shape type="disk"/>
    <shape type="sphere"><point name="center" x="1" y="2" z="3"/><float name="radius" value="0.5"/></shape>
    <shape type="cube"><boolean name="flip_normals" value="true"/></shape>)"));
  EXPECT_NEAR(s.shapes[0].mesh.area(), 4.0, 1e-6);
  EXPECT_NEAR(s.shapes[1].mesh.area(), 24.0, 1e-5);
  ASSERT_TRUE(s.shapes[2].exact);  // exact, as the sphere
  EXPECT_NEAR(s.shapes[2].area(), M_PI, 1e-6);
  ASSERT_TRUE(s.shapes[3].exact);               // exact: its centre and radius, no triangles
  EXPECT_NEAR(s.shapes[3].area(), M_PI, 1e-6);  // 4π r², r = 1/2
  expect_vec(s.shapes[3].exact->origin, Vec3(1, 2, 3));
  EXPECT_FLOAT_EQ(s.shapes[3].exact->radius(), 0.5f);
  EXPECT_TRUE(s.shapes[3].mesh.triangles.empty());
  // Cube faces point outwards; flip_normals turns them (winding included) inwards.
  for (const auto& [index, sign] : {std::pair{1, 1.0f}, std::pair{4, -1.0f}}) {
    const auto& cube = s.shapes[std::size_t(index)].mesh;
    for (const auto& t : cube.triangles) {
      const Vec3 c = (cube.positions[t.x] + cube.positions[t.y] + cube.positions[t.z]) / 3.0f;
      const Vec3 n = glm::cross(cube.positions[t.y] - cube.positions[t.x], cube.positions[t.z] - cube.positions[t.x]);
      EXPECT_GT(glm::dot(n, c) * sign, 0.0f);
    }
  }
}

TEST_F(Loader, ObjMeshesWithAndWithoutFaceNormals) {
  write("quad.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  const auto s = scene::load_scene(scene(R"(<shape type="obj"><string name="filename" value="quad.obj"/></shape>
    <shape type="obj"><string name="filename" value="quad.obj"/><boolean name="face_normals" value="true"/>
      <transform name="to_world"><scale value="2"/></transform></shape>)"));
  ASSERT_EQ(s.shapes[0].mesh.triangles.size(), 2u);  // the quad is fanned
  EXPECT_EQ(s.shapes[0].mesh.normals.size(), 4u);
  EXPECT_NEAR(s.shapes[0].mesh.uvs[2].y, 0.0f, 1e-6f);  // v flipped: (1, 1) → (1, 0)
  EXPECT_TRUE(s.shapes[1].mesh.normals.empty());
  EXPECT_NEAR(s.shapes[1].mesh.area(), 4.0, 1e-6);
}

std::string ply_header(const char* format) {
  return std::string("ply\nformat ") + format +
         " 1.0\ncomment a unit square\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST_F(Loader, PlyAsciiAndBinary) {
  write("ascii.ply", ply_header("ascii") + "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
  std::string bin = ply_header("binary_little_endian");
  const float v[4][5] = {{0, 0, 0, 0, 0}, {1, 0, 0, 1, 0}, {1, 1, 0, 1, 1}, {0, 1, 0, 0, 1}};
  bin.append(reinterpret_cast<const char*>(v), sizeof v);
  bin.push_back(char(4));
  const std::int32_t idx[4] = {0, 1, 2, 3};
  bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
  write("binary.ply", bin);
  std::string big = ply_header("binary_big_endian");
  for (const auto& row : v)
    for (float f : row) {
      char b[4];
      std::memcpy(b, &f, 4);
      big.append({b[3], b[2], b[1], b[0]});
    }
  big.push_back(char(4));
  for (std::int32_t i : idx) big.append({0, 0, 0, char(i)});
  write("big.ply", big);
  const auto s = scene::load_scene(scene(R"(<shape type="ply"><string name="filename" value="ascii.ply"/></shape>
    <shape type="ply"><string name="filename" value="binary.ply"/></shape>
    <shape type="ply"><string name="filename" value="big.ply"/></shape>)"));
  for (const auto& shape : s.shapes) {
    EXPECT_EQ(shape.mesh.triangles.size(), 2u);
    EXPECT_NEAR(shape.mesh.area(), 1.0, 1e-6);
    // As stored: Mitsuba 3 flips only obj's v (3.9.1's vertex_texcoords_buffer of a PLY holds the file's values).
    // A flip here mirrored every texture on a PLY, e.g. a Blender-exported crate.
    EXPECT_NEAR(shape.mesh.uvs[3].y, 1.0f, 1e-6f);
    EXPECT_FALSE(shape.mesh.normals.empty());  // computed, as Mitsuba does for meshes without normals
  }
}

// A Mitsuba .serialized file (version 4) holding `count` copies of a unit triangle scaled by 1, 2, ...
std::string serialized(int count) {
  std::string file;
  std::vector<std::uint64_t> offsets;
  for (int k = 0; k < count; ++k) {
    std::string raw;
    auto put = [&](const auto& x) { raw.append(reinterpret_cast<const char*>(&x), sizeof x); };
    put(std::uint32_t(0x1000));  // single precision, no normals/uvs
    raw.append("tri", 4);
    put(std::uint64_t(3));
    put(std::uint64_t(1));
    const float s = float(k + 1);
    for (float f : {0.0f, 0.0f, 0.0f, s, 0.0f, 0.0f, 0.0f, s, 0.0f}) put(f);
    for (std::uint32_t i : {0u, 1u, 2u}) put(i);
    uLongf size = compressBound(uLong(raw.size()));
    std::string z(size, '\0');
    compress(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
    offsets.push_back(file.size());
    file.append({char(0x1C), char(0x04), char(4), char(0)});
    file.append(z.data(), size);
  }
  for (auto o : offsets) file.append(reinterpret_cast<const char*>(&o), 8);
  const auto n = std::uint32_t(count);
  file.append(reinterpret_cast<const char*>(&n), 4);
  return file;
}

TEST_F(Loader, SerializedPicksTheShapeIndex) {
  write("mesh.serialized", serialized(3));
  const auto s = scene::load_scene(scene(R"(
    <shape type="serialized"><string name="filename" value="mesh.serialized"/></shape>
    <shape type="serialized"><string name="filename" value="mesh.serialized"/>
      <integer name="shape_index" value="2"/></shape>)"));
  EXPECT_NEAR(s.shapes[0].mesh.area(), 0.5, 1e-6);
  EXPECT_NEAR(s.shapes[1].mesh.area(), 4.5, 1e-5);
}

template <typename T>
const T* as(const scene::Scene& s, std::size_t shape) {
  return dynamic_cast<const T*>(&s.bsdf(s.shapes[shape]));
}

TEST_F(Loader, EveryMaterial) {
  const auto s = scene::load_scene(scene(R"(
    <shape type="rectangle"><bsdf type="diffuse"/></shape>
    <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="roughconductor"><string name="distribution" value="ggx"/>
      <float name="alpha" value="0.3"/><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.1"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="plastic"/></shape>
    <shape type="rectangle"><bsdf type="roughplastic"><float name="alpha" value="0.2"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="dielectric"><string name="int_ior" value="water"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="thindielectric"/></shape>
    <shape type="rectangle"><bsdf type="roughdielectric"><float name="alpha" value="0.1"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="bumpmap"><texture name="map" type="checkerboard"/><bsdf type="diffuse"/></bsdf>
    </shape>)"));
  EXPECT_TRUE(as<scene::Diffuse>(s, 0));
  EXPECT_TRUE(as<scene::TwoSided>(s, 1));
  ASSERT_TRUE(as<scene::Conductor>(s, 2));
  EXPECT_FALSE(as<scene::Conductor>(s, 2)->has_non_delta());
  EXPECT_FLOAT_EQ(as<scene::Conductor>(s, 3)->roughness(), 0.3f);
  EXPECT_TRUE(as<scene::Plastic>(s, 4));
  EXPECT_FLOAT_EQ(as<scene::Plastic>(s, 5)->roughness(), 0.2f);
  ASSERT_TRUE(as<scene::Dielectric>(s, 6));
  EXPECT_FALSE(as<scene::Dielectric>(s, 7)->has_non_delta());
  EXPECT_TRUE(as<scene::Dielectric>(s, 8)->has_non_delta());
  ASSERT_TRUE(as<scene::Mask>(s, 9));
  EXPECT_FLOAT_EQ(as<scene::Mask>(s, 9)->opacity()->eval(Vec2(0)).x, 0.3f);
  ASSERT_TRUE(as<scene::BumpMapped>(s, 10));
  EXPECT_TRUE(as<scene::BumpMapped>(s, 10)->bump());
  // Water's IOR (1.333): the normal-incidence reflectance of the dielectric is ((η−1)/(η+1))².
  const auto* water = as<scene::Dielectric>(s, 6);
  const auto r = water->sample(Vec2(0), Vec3(0, 0, 1), 0.0f, Vec2(0.5f));
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->pdf, std::pow(0.333f / 2.333f, 2.0f), 1e-4f);
}

TEST_F(Loader, TexturesBitmapAndCheckerboard) {
  image::Image img(2, 1);
  img.pixel(0, 0)[0] = img.pixel(0, 0)[1] = img.pixel(0, 0)[2] = 0.5f;  // linear 0.5 → sRGB byte 188
  img.pixel(1, 0)[0] = 1.0f;
  image::write_png(dir_ / "tex.png", img);
  const auto s = scene::load_scene(scene(R"(
    <texture type="bitmap" id="tex"><string name="filename" value="tex.png"/>
      <string name="filter_type" value="nearest"/></texture>
    <shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="tex"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="bitmap">
      <string name="filename" value="tex.png"/><boolean name="raw" value="true"/>
      <string name="filter_type" value="nearest"/></texture></bsdf></shape>
    <shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="checkerboard">
      <rgb name="color0" value="0.1"/><rgb name="color1" value="0.9"/>
      <transform name="to_uv"><scale x="2" y="2"/></transform></texture></bsdf></shape>)"));
  const auto& srgb = s.bsdf(s.shapes[0]);
  EXPECT_NEAR(srgb.albedo(Vec2(0.25f, 0.5f)).x, 0.5f, 0.005f);  // decoded back to linear
  EXPECT_NEAR(srgb.albedo(Vec2(0.75f, 0.5f)).y, 0.0f, 1e-6f);
  EXPECT_NEAR(s.bsdf(s.shapes[1]).albedo(Vec2(0.25f, 0.5f)).x, 188.0f / 255.0f, 0.003f);  // raw: the byte value
  const auto& checker = s.bsdf(s.shapes[2]);
  EXPECT_FLOAT_EQ(checker.albedo(Vec2(0.1f, 0.1f)).x, 0.1f);  // uv ×2 = (0.2, 0.2): same halves → colour 0
  EXPECT_FLOAT_EQ(checker.albedo(Vec2(0.3f, 0.1f)).x, 0.9f);  // (0.6, 0.2): different halves → colour 1
  EXPECT_FLOAT_EQ(checker.albedo(Vec2(0.8f, 0.8f)).x, 0.1f);  // (1.6, 1.6): wraps around
}

// Where a BSDF reads a texture as a number, Mitsuba 3 calls eval_1, which differs from the colour read (eval): a
// checkerboard's colours change places, an rgb becomes its channel mean and a bitmap its luminance (the numbers are
// Mitsuba 3.9.1's, from tests/scene/mitsuba_textures.py). The members of the class: a roughness, a principled
// parameter, a blend's weight and a mask's opacity.
TEST_F(Loader, TexturesReadAsNumbersFollowMitsubasEval1) {
  image::Image img(2, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      img.pixel(x, y)[0] = 0.2f;
      img.pixel(x, y)[1] = 0.5f;
      img.pixel(x, y)[2] = 0.9f;
    }
  image::write_exr(dir_ / "rgb.exr", img);
  const auto named = [](const std::string& name) {
    return R"(<texture name=")" + name + R"(" type="checkerboard">
      <float name="color0" value="0.05"/><float name="color1" value="0.3"/>
      <transform name="to_uv"><scale x="2" y="2"/></transform></texture>)";
  };
  const auto s = scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="roughconductor">)" + named("alpha") +
                                         R"(</bsdf></shape>
    <shape type="rectangle"><bsdf type="roughconductor"><float name="alpha" value="0.05"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="principled">)" +
                                         named("roughness") + R"(</bsdf></shape>
    <shape type="rectangle"><bsdf type="principled"><float name="roughness" value="0.05"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="principled"><float name="roughness" value="0.3"/></bsdf></shape>
    <shape type="rectangle"><bsdf type="mask"><rgb name="opacity" value="0.2 0.5 0.9"/><bsdf type="diffuse"/>
      </bsdf></shape>
    <shape type="rectangle"><bsdf type="blendbsdf"><texture name="weight" type="bitmap">
      <string name="filename" value="rgb.exr"/></texture>
      <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
      <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></bsdf></shape>)"));
  const Vec3 wo = glm::normalize(Vec3(0.3f, 0.1f, 1.0f)), wi = glm::normalize(Vec3(-0.2f, 0.25f, 1.0f));
  const auto f = [&](int shape, const Vec2& uv) { return s.bsdf(s.shapes[shape]).eval(uv, wo, wi).x; };
  const Vec2 same(0.1f, 0.1f), different(0.3f, 0.1f);          // through to_uv: (0.2, 0.2) and (0.6, 0.2)
  ASSERT_GT(std::fabs(f(1, same) / f(2, same) - 1.0f), 0.1f);  // the two roughnesses differ visibly here
  for (const int textured : {0, 3}) {
    EXPECT_FLOAT_EQ(f(textured, same), f(textured + 2, same)) << "shape " << textured << ": colour 1, 0.3";
    EXPECT_FLOAT_EQ(f(textured, different), f(textured + 1, different)) << "shape " << textured << ": colour 0";
  }
  ASSERT_TRUE(as<scene::Mask>(s, 6));
  EXPECT_FLOAT_EQ(as<scene::Mask>(s, 6)->opacity()->eval_1(Vec2(0.5f)), 0.5333333611488342f);
  EXPECT_NEAR(s.bsdf(s.shapes[7]).albedo(Vec2(0.5f)).x, 0.4650663137435913f, 1e-6f);
}

// Mitsuba 3's bitmap `format`, the precision of the stored texels; the values below are what Mitsuba 3.9.1's
// bitmap returns for an EXR of 0.3, 2.0, 0.001, 0.7 (nearest lookups, raw or not).
TEST_F(Loader, BitmapFormatStoresTexelsAtItsPrecision) {
  image::Image img(4, 1);
  const float values[] = {0.3f, 2.0f, 0.001f, 0.7f};
  for (int x = 0; x < 4; ++x) img.pixel(x, 0)[0] = img.pixel(x, 0)[1] = img.pixel(x, 0)[2] = values[x];
  image::write_exr(dir_ / "tex.exr", img);
  const auto texel = [&](const std::string& format, int x) {
    const auto s = scene::load_scene(scene(R"(<shape type="rectangle"><bsdf type="diffuse">
        <texture name="reflectance" type="bitmap"><string name="filename" value="tex.exr"/>
        <string name="filter_type" value="nearest"/><string name="format" value=")" +
                                               format + R"("/></texture></bsdf></shape>)",
                                           "3.0.0", format + ".xml"));
    return s.bsdf(s.shapes[0]).albedo(Vec2((float(x) + 0.5f) / 4.0f, 0.5f)).x;
  };
  const std::pair<std::string, std::array<float, 4>> expected[] = {
      {"auto", {0.3f, 2.0f, 0.001f, 0.7f}},
      {"variant", {0.3f, 2.0f, 0.001f, 0.7f}},
      {"float16", {0.300049f, 2.0f, 0.001f, 0.700195f}},
      {"uint8", {0.298039f, 1.0f, 0.0f, 0.701961f}},
  };
  for (const auto& [format, want] : expected)
    for (int x = 0; x < 4; ++x) EXPECT_NEAR(texel(format, x), want[std::size_t(x)], 2e-6f) << format << " " << x;
  EXPECT_THROW(texel("fixed16", 0), InputError);
}

// The reference converges to what the scene's integrator renders: the innermost transport integrator's path length
// (through aov and moment wrappers), `direct` as emission plus one bounce, its rr_depth; an integrator clradiosity
// does not implement renders as `path` (and says so on stderr); impossible depths are refused naming them.
TEST_F(Loader, TheIntegratorSetsWhatTheReferenceRenders) {
  const auto load = [&](const std::string& integrator) { return scene::load_scene(scene(integrator)); };
  EXPECT_EQ(load("").max_depth, -1);
  EXPECT_EQ(load(R"(<integrator type="direct"/>)").max_depth, 2);
  EXPECT_EQ(load(R"(<integrator type="direct"><integer name="emitter_samples" value="4"/></integrator>)").max_depth, 2);
  auto s = load(R"(<integrator type="volpath"><integer name="max_depth" value="7"/>
                     <integer name="rr_depth" value="9"/></integrator>)");
  EXPECT_EQ(s.max_depth, 7);
  EXPECT_EQ(s.rr_depth, 9);
  EXPECT_EQ(load(R"(<integrator type="path"/>)").rr_depth, std::nullopt);
  EXPECT_EQ(load(R"(<integrator type="aov"><string name="aovs" value="nn:sh_normal"/>
                      <integrator type="path"><integer name="max_depth" value="4"/></integrator></integrator>)")
                .max_depth,
            4);
  EXPECT_EQ(load(R"(<integrator type="moment"><integrator type="direct"/></integrator>)").max_depth, 2);
  // A max_depth on the wrapper is not the inner integrator's.
  EXPECT_EQ(
      load(R"(<integrator type="moment"><integer name="max_depth" value="3"/><integrator type="path"/></integrator>)")
          .max_depth,
      -1);
  EXPECT_EQ(load(R"(<integrator type="depth"/>)").max_depth, -1);
  // What `reference` says of them: nothing for what it implements, one line for a wrapper or an unknown type.
  EXPECT_EQ(load(R"(<integrator type="path"/>)").integrator_note, "");
  EXPECT_THAT(load(R"(<integrator type="depth"/>)").integrator_note,
              ::testing::HasSubstr("'depth' is not implemented"));
  EXPECT_THAT(load(R"(<integrator type="moment"><integrator type="direct"/></integrator>)").integrator_note,
              ::testing::HasSubstr("'moment' wraps 'direct'"));
  EXPECT_THROW(load(R"(<integrator type="path"><integer name="max_depth" value="-4"/></integrator>)"), InputError);
  EXPECT_THROW(load(R"(<integrator type="path"><integer name="rr_depth" value="0"/></integrator>)"), InputError);
}

TEST_F(Loader, EmittersAndIgnoredElements) {
  image::Image env(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) env.pixel(x, y)[0] = env.pixel(x, y)[1] = env.pixel(x, y)[2] = float(1 + x + y);
  image::write_exr(dir_ / "env.exr", env);
  auto s = scene::load_scene(scene(R"(
    <integrator type="path"><integer name="max_depth" value="5"/></integrator>
    <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
    <emitter type="envmap"><string name="filename" value="env.exr"/><float name="scale" value="2"/></emitter>)"));
  EXPECT_EQ(s.max_depth, 5);
  expect_vec(s.shapes[0].radiance, Vec3(1, 2, 3));
  ASSERT_TRUE(s.environment);
  // Straight up (+y) is the top row (v = 0): pixel values 1..8 there, times the scale.
  const Rgb up = s.environment->eval(Vec3(0, 1, 0));
  EXPECT_GE(up.x, 2.0f);
  EXPECT_LE(up.x, 16.0f);
  s = scene::load_scene(scene(R"(<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>)"));
  EXPECT_FLOAT_EQ(s.environment->eval(Vec3(0.3f, -0.2f, 0.9f)).x, 0.5f);
}

}  // namespace
}  // namespace clr::test
