// The scene's memory budget (scene/memory_budget.hpp): every part that can cost more memory than its file's size —
// decoded images, environment maps, compressed meshes, instances, tessellation — is weighed before it is spent and
// refused by name beyond CLRADIOSITY_MEMORY_LIMIT.
#include "scene/memory_budget.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdlib>

#include "common/error.hpp"
#include "image/image.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;

// Sets the limit for one test and restores the environment after it.
class MemoryBudget : public SceneFiles {
 protected:
  void TearDown() override {
    unsetenv("CLRADIOSITY_MEMORY_LIMIT");
    SceneFiles::TearDown();
  }
  static void limit(const char* value) { setenv("CLRADIOSITY_MEMORY_LIMIT", value, 1); }
  std::string refusal(const std::string& body) {
    try {
      scene::load_scene(scene(body));
    } catch (const InputError& e) {
      return e.what();
    }
    return "(loaded)";
  }
  void image(const std::string& name, int w, int h) const { image::write_png(dir_ / name, image::Image(w, h)); }
};

TEST_F(MemoryBudget, ImagesAreWeighedFromTheirHeadersBeforeTheyAreDecoded) {
  // A black 1024² PNG is a few kB on disk and 12 MB as float texels; 256² is 768 kB.
  image("big.png", 1024, 1024);
  image("small.png", 256, 256);
  limit("4M");
  const auto textured = [](const char* file) {
    return std::string(R"(<shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="bitmap">
      <string name="filename" value=")") +
           file + R"("/></texture></bsdf></shape>)";
  };
  EXPECT_EQ(refusal(textured("small.png")), "(loaded)");
  const std::string why = refusal(textured("big.png"));
  EXPECT_THAT(why,
              HasSubstr("big.png would bring the scene to about 12 MB of memory (geometry under 1 MB, images 12 MB)"));
  EXPECT_THAT(why, HasSubstr("more than its limit of 4 MB (CLRADIOSITY_MEMORY_LIMIT)"));
  // Six small textures fit one by one and not together; a texture read twice the same way is held once.
  std::string six, twice;
  for (int i = 0; i < 6; ++i) {
    image("t" + std::to_string(i) + ".png", 256, 256);
    six += textured(("t" + std::to_string(i) + ".png").c_str());
    twice += textured("small.png");
  }
  EXPECT_THAT(refusal(six), HasSubstr("t5.png would bring the scene to about"));
  EXPECT_EQ(refusal(twice), "(loaded)");
  // An environment map holds its sampling tables too (3 MB at 512 × 256), and its element is named.
  image::Image sky_image(512, 256);
  sky_image.rgb.assign(sky_image.rgb.size(), 1.0f);
  image::write_exr(dir_ / "sky.exr", sky_image);
  const std::string sky_xml = R"(<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>)";
  limit("2M");
  const std::string sky = refusal(sky_xml);
  EXPECT_THAT(sky, HasSubstr("<emitter type=\"envmap\">: image "));
  EXPECT_THAT(sky, HasSubstr("sky.exr would bring the scene to about 3 MB"));
  limit("4M");
  EXPECT_EQ(refusal(sky_xml), "(loaded)");
}

TEST_F(MemoryBudget, GeometryIsWeighedShapeByShapeWithInstancesAndTessellationCounted) {
  limit("64M");
  // Exact spheres cost next to nothing: 10 000 of them fit in 64 MB.
  std::string spheres;
  for (int i = 0; i < 10000; ++i)
    spheres += R"(<shape type="sphere"><point name="center" x=")" + std::to_string(i) + R"(" y="0" z="0"/></shape>)";
  EXPECT_EQ(refusal(spheres), "(loaded)");
  // A sphere stretched into an ellipsoid is tessellated (262 144 triangles, ~38 MB): the second one is refused.
  const auto ellipsoid = [](const std::string& id) {
    return R"(<shape type="sphere" id=")" + id + R"("><transform name="to_world"><scale z="2"/></transform></shape>)";
  };
  EXPECT_EQ(refusal(ellipsoid("egg")), "(loaded)");
  EXPECT_THAT(refusal(ellipsoid("egg") + ellipsoid("egg2")),
              HasSubstr("shape 'egg2' would bring the scene to about 7"));
  // Instances count every copy before copying: a group of one ellipsoid (36 MB) and its copies reach 256 MB at the
  // seventh.
  limit("256M");
  std::string instances = R"(<shape type="shapegroup" id="g">)" + ellipsoid("egg") + "</shape>";
  for (int i = 0; i < 10; ++i)
    instances += R"(<shape type="instance" id="i)" + std::to_string(i) + R"("><ref id="g"/></shape>)";
  const std::string why = refusal(instances);
  EXPECT_THAT(why, HasSubstr("<shape type=\"instance\" id=\"i6\">: instance 'i6' would bring the scene to about"));
  EXPECT_THAT(why, HasSubstr("more than its limit of 256 MB"));
}

TEST_F(MemoryBudget, ACompressedMeshIsWeighedFromItsCountsBeforeItIsInflated) {
  // One serialized shape of 2^20 vertices and triangles, all zeros: 24 MB inflated from ~25 kB, ~200 MB as a mesh.
  const std::uint64_t n = std::uint64_t(1) << 20;
  std::string raw;
  auto put = [&](const auto& x) { raw.append(reinterpret_cast<const char*>(&x), sizeof x); };
  put(std::uint32_t(0x1000));
  raw.append("z", 2);
  put(n);
  put(n);
  raw.append(n * 12 + n * 12, '\0');
  uLongf size = compressBound(uLong(raw.size()));
  std::string z(size, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
  std::string file{char(0x1C), char(0x04), char(4), char(0)};
  file.append(z.data(), size);
  const std::uint64_t offset = 0;
  const std::uint32_t count = 1;
  file.append(reinterpret_cast<const char*>(&offset), 8);
  file.append(reinterpret_cast<const char*>(&count), 4);
  write("bomb.serialized", file);
  ASSERT_LT(file.size(), 100000u);
  limit("64M");
  const std::string why =
      refusal(R"(<shape type="serialized"><string name="filename" value="bomb.serialized"/></shape>)");
  EXPECT_THAT(why, HasSubstr("bomb.serialized would bring the scene to about 192 MB"));
}

TEST_F(MemoryBudget, TheLimitIsAPositiveSizeOrRefusedByName) {
  for (const char* bad : {"lots", "0", "-5G", "12Q", "1e30", "8GG", ""}) {
    limit(bad);
    const std::string why = refusal(R"(<shape type="rectangle"/>)");
    if (*bad == '\0') {
      EXPECT_EQ(why, "(loaded)") << "an empty variable is no limit";
      continue;
    }
    EXPECT_THAT(why, HasSubstr("CLRADIOSITY_MEMORY_LIMIT='" + std::string(bad) + "' is no memory size")) << bad;
  }
  for (const char* good : {"1048576", "1.5G", "512M", "64MiB", "2t", "4KB"}) {
    limit(good);
    EXPECT_NO_THROW(scene::MemoryBudget()) << good;
  }
  limit("1.5G");
  EXPECT_EQ(scene::MemoryBudget().limit(), std::uint64_t(1.5 * 1073741824.0));
}

TEST_F(MemoryBudget, TheCommandLineRefusesBeforeRenderingAndWritesNothing) {
  image("big.png", 1024, 1024);
  const auto file = scene(R"(<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
      <integer name="height" value="8"/></film></sensor>
    <emitter type="constant"/>
    <shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="bitmap">
      <string name="filename" value="big.png"/></texture></bsdf></shape>)");
  const auto out = dir_ / "out.exr";
  const auto r = run_cli("reference " + file.string() + " --spp 1 -o " + out.string(), "CLRADIOSITY_MEMORY_LIMIT=4M");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("big.png would bring the scene to about 12 MB"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(
      run_cli("reference " + file.string() + " --spp 1 -o " + out.string(), "CLRADIOSITY_MEMORY_LIMIT=64M").exit_code,
      0);
}

}  // namespace
}  // namespace clr::test
