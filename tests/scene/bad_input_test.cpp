// Every class of bad scene input ends `clradiosity reference` with exit code 2 and one line naming the file, the
// line and the element at fault (docs/design.md §4).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/scene_files.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;

class BadInput : public SceneFiles {
 protected:
  // Runs the reference on `file` and checks the exit code and the one-line message.
  void expect_rejected(const std::filesystem::path& file, const std::vector<std::string>& message_parts) {
    const auto r = run_cli("reference '" + file.string() + "' --spp 1 --width 4 --height 4 -o '" +
                           (dir_ / "out.exr").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& part : message_parts) EXPECT_THAT(r.err, HasSubstr(part));
    EXPECT_FALSE(std::filesystem::exists(dir_ / "out.exr"));
  }
};

TEST_F(BadInput, MalformedXml) {
  expect_rejected(write("scene.xml", "<scene version=\"3.0.0\">\n  <shape type=\"rectangle\">\n</scene>\n"),
                  {"scene.xml:3:", "malformed XML"});
}

TEST_F(BadInput, MissingFiles) {
  expect_rejected(dir_ / "nonexistent.xml", {"nonexistent.xml", "not found"});
  expect_rejected(scene("<shape type=\"obj\">\n<string name=\"filename\" value=\"missing.obj\"/></shape>"),
                  {"scene.xml:2:", "<shape type=\"obj\">", "missing.obj", "not found"});
  expect_rejected(scene("<include filename=\"other.xml\"/>"), {"scene.xml:2:", "<include>", "other.xml"});
  expect_rejected(scene(R"(<shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="bitmap">
    <string name="filename" value="missing.png"/></texture></bsdf></shape>)"),
                  {"scene.xml:2:", "<texture name=\"reflectance\" type=\"bitmap\">", "missing.png"});
}

TEST_F(BadInput, UnsupportedPlugins) {
  expect_rejected(scene("<shape type=\"rectangle\">\n  <bsdf type=\"velvet\"/>\n</shape>"),
                  {"scene.xml:3:", "<bsdf type=\"velvet\">", "unsupported BSDF type"});
  // Out of scope on purpose: refused naming why.
  expect_rejected(scene("<shape type=\"rectangle\">\n  <bsdf type=\"hair\"/>\n</shape>"),
                  {"scene.xml:3:", "<bsdf type=\"hair\">", "not surfaces"});
  expect_rejected(scene("<shape type=\"teapot\"/>"), {"scene.xml:2:", "unsupported shape type 'teapot'"});
  expect_rejected(scene("<emitter type=\"pulsar\"/>"), {"scene.xml:2:", "unsupported emitter type 'pulsar'"});
  expect_rejected(scene("<sensor type=\"fisheye\"/>"), {"scene.xml:2:", "unsupported sensor type"});
  expect_rejected(scene("<volume/>"), {"scene.xml:2:", "<volume>", "3D grids"});
  expect_rejected(scene("<unicorn/>"), {"scene.xml:2:", "<unicorn>", "unsupported element"});
  // A 3D grid texture, with its grid nested or not: named as what it is.
  expect_rejected(scene("<shape type=\"cube\"><bsdf type=\"diffuse\">\n<texture type=\"volume\" "
                        "name=\"reflectance\"><volume type=\"constvolume\" name=\"volume\"/></texture></bsdf></shape>"),
                  {"scene.xml:3:", "3D grid textures (volume) are not supported"});
  expect_rejected(scene("<shape type=\"cube\"><bsdf type=\"diffuse\">\n<texture type=\"bitmap\" "
                        "name=\"reflectance\"><volume type=\"gridvolume\" name=\"volume\"/></texture></bsdf></shape>"),
                  {"scene.xml:3:", "<volume", "3D grids"});
}

TEST_F(BadInput, BadNumbers) {
  expect_rejected(scene("<sensor type=\"perspective\">\n<float name=\"fov\" value=\"4x5\"/></sensor>"),
                  {"scene.xml:3:", "<float name=\"fov\">", "malformed number '4x5'"});
  expect_rejected(scene("<shape type=\"rectangle\"><bsdf type=\"diffuse\">\n"
                        "<rgb name=\"reflectance\" value=\"0.5, nan, 0.5\"/></bsdf></shape>"),
                  {"scene.xml:3:", "malformed number 'nan'"});
  expect_rejected(scene("<shape type=\"rectangle\"><transform name=\"to_world\">\n<matrix value=\"1 2 3\"/>"
                        "</transform></shape>"),
                  {"scene.xml:3:", "<matrix>", "16"});
  expect_rejected(scene("<sensor type=\"perspective\">\n<float name=\"fov\" value=\"$undefined\"/></sensor>"),
                  {"scene.xml:3:", "undefined parameter '$undefined'"});
  expect_rejected(scene("<shape type=\"rectangle\"><bsdf type=\"diffuse\">\n"
                        "<rgb name=\"reflectence\" value=\"0.5\"/></bsdf></shape>"),
                  {"scene.xml:3:", "<rgb name=\"reflectence\">", "unused property"});
}

TEST_F(BadInput, BadReferences) {
  expect_rejected(scene("<shape type=\"rectangle\">\n  <ref id=\"nothing\"/>\n</shape>"),
                  {"scene.xml:3:", "<ref id=\"nothing\">", "unknown id 'nothing'"});
  expect_rejected(scene("<texture type=\"checkerboard\" id=\"t\"/>\n<shape type=\"rectangle\"><ref id=\"t\"/></shape>"),
                  {"scene.xml:3:", "does not name a BSDF"});
  expect_rejected(scene("<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>"),
                  {"scene.xml:3:", "duplicate id 'a'"});
}

TEST_F(BadInput, NanGeometry) {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float v[9] = {0, 0, 0, 1, 0, 0, std::nanf(""), 1, 0};
  ply.append(reinterpret_cast<const char*>(v), sizeof v);
  ply.push_back(char(3));
  const std::int32_t idx[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(idx), sizeof idx);
  write("nan.ply", ply);
  expect_rejected(scene("<shape type=\"ply\">\n<string name=\"filename\" value=\"nan.ply\"/></shape>"),
                  {"scene.xml:2:", "<shape type=\"ply\">", "not finite"});
  expect_rejected(scene("<shape type=\"rectangle\"><transform name=\"to_world\">\n"
                        "<scale value=\"1e30\"/><scale value=\"1e30\"/></transform></shape>"),
                  {"scene.xml:2:", "not finite"});
}

TEST_F(BadInput, VersionAndRoot) {
  expect_rejected(write("scene.xml", "<scene>\n</scene>\n"), {"scene.xml:1:", "missing attribute 'version'"});
  expect_rejected(write("scene.xml", "<scene version=\"9.0\"/>\n"), {"unsupported scene version '9.0'"});
  expect_rejected(write("scene.xml", "<world version=\"3.0.0\"/>\n"), {"root element must be <scene>"});
}

}  // namespace
}  // namespace clr::test
