// Mitsuba 3's `principled` and `principledthin` BSDFs: eval against Mitsuba's own values at fixed directions,
// reflection and transmission from either side (the table comes from tests/scene/mitsuba_principled.py), and the
// loader's refusals. Sampling (χ², weights) is in bsdf_test.cpp.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "scene/bsdfs.hpp"
#include "scene/scene.hpp"
#include "scene_files.hpp"

namespace clr::test {
namespace {

using scene::Rgb;
using scene::Vec3;

Vec3 direction(float theta_degrees, float phi_degrees) {
  const float t = theta_degrees * scene::kPi / 180.0f, p = phi_degrees * scene::kPi / 180.0f;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// The same materials as the script's dictionaries, as scene XML.
std::string material(const std::string& name) {
  if (name == "default") return R"(<bsdf type="principled"/>)";
  if (name == "metallic_aniso")
    return R"(<bsdf type="principled"><rgb name="base_color" value="0.9, 0.6, 0.2"/>
      <float name="metallic" value="0.7"/><float name="roughness" value="0.3"/>
      <float name="anisotropic" value="0.6"/><float name="spec_tint" value="0.4"/></bsdf>)";
  if (name == "coat_sheen_flat")
    return R"(<bsdf type="principled"><rgb name="base_color" value="0.2, 0.5, 0.8"/>
      <float name="clearcoat" value="0.8"/><float name="clearcoat_gloss" value="0.5"/>
      <float name="sheen" value="0.6"/><float name="sheen_tint" value="0.5"/><float name="flatness" value="0.4"/>
      <float name="roughness" value="0.6"/></bsdf>)";
  if (name == "thin_default") return R"(<bsdf type="principledthin"/>)";
  if (name == "thin_full")
    return R"(<bsdf type="principledthin"><rgb name="base_color" value="0.7, 0.4, 0.2"/>
      <float name="spec_trans" value="0.6"/><float name="diff_trans" value="0.8"/><float name="roughness" value="0.4"/>
      <float name="eta" value="1.4"/><float name="spec_tint" value="0.5"/><float name="sheen" value="0.5"/>
      <float name="sheen_tint" value="0.3"/><float name="flatness" value="0.3"/><float name="anisotropic" value="0.4"/>
      </bsdf>)";
  if (name == "spec_trans")
    return R"(<bsdf type="principled"><rgb name="base_color" value="0.8, 0.9, 0.6"/>
      <float name="spec_trans" value="0.7"/><float name="roughness" value="0.3"/><float name="eta" value="1.5"/>
      <float name="metallic" value="0.1"/><float name="clearcoat" value="0.3"/><float name="sheen" value="0.2"/></bsdf>)";
  if (name == "spec_trans_full_specular")
    return R"(<bsdf type="principled"><float name="spec_trans" value="1"/><float name="roughness" value="0.5"/>
      <float name="specular" value="0.3"/></bsdf>)";
  return R"(<bsdf type="principled"><rgb name="base_color" value="0.3, 0.3, 0.3"/>
      <float name="roughness" value="0.2"/><float name="eta" value="1.8"/><float name="spec_tint" value="1"/></bsdf>)";
}

struct MitsubaValue {
  const char* material;
  float wo[2], wi[2];  // θ, φ in degrees; wo towards the viewer, wi towards the light (θ > 90°: below)
  float rgb[3];        // f·cos θi
};

class Principled : public SceneFiles {
 protected:
  // The loader's message for a rectangle with this BSDF, or "accepted".
  std::string refused(const std::string& bsdf) {
    try {
      scene::load_scene(scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  }
};

TEST_F(Principled, EvalMatchesMitsuba3) {
  const MitsubaValue table[] = {
      {"default", {30, 20}, {40, 200}, {0.172142f, 0.172142f, 0.172142f}},
      {"default", {60, 0}, {55, 180}, {0.2653967f, 0.2653967f, 0.2653967f}},
      {"default", {10, 90}, {70, 45}, {0.05697767f, 0.05697767f, 0.05697767f}},
      {"default", {75, 30}, {20, 250}, {0.1573931f, 0.1573931f, 0.1573931f}},
      {"default", {45, 0}, {45, 180}, {0.200282f, 0.200282f, 0.200282f}},
      {"metallic_aniso", {30, 20}, {40, 200}, {2.868927f, 1.924082f, 0.6642899f}},
      {"metallic_aniso", {60, 0}, {55, 180}, {10.33661f, 7.055972f, 2.681789f}},
      {"metallic_aniso", {10, 90}, {70, 45}, {0.03030776f, 0.02020968f, 0.006745578f}},
      {"metallic_aniso", {75, 30}, {20, 250}, {0.1412398f, 0.09452306f, 0.03223404f}},
      {"metallic_aniso", {45, 0}, {45, 180}, {8.961263f, 6.023808f, 2.107198f}},
      {"coat_sheen_flat", {30, 20}, {40, 200}, {0.1028299f, 0.1691691f, 0.2355082f}},
      {"coat_sheen_flat", {60, 0}, {55, 180}, {0.2015776f, 0.2616737f, 0.3217697f}},
      {"coat_sheen_flat", {10, 90}, {70, 45}, {0.02365141f, 0.0561693f, 0.08868721f}},
      {"coat_sheen_flat", {75, 30}, {20, 250}, {0.07328533f, 0.163758f, 0.2542306f}},
      {"coat_sheen_flat", {45, 0}, {45, 180}, {0.2048893f, 0.2695728f, 0.3342562f}},
      {"glossy_eta", {30, 20}, {40, 200}, {0.2156823f, 0.2156823f, 0.2156823f}},
      {"glossy_eta", {60, 0}, {55, 180}, {2.151889f, 2.151889f, 2.151889f}},
      {"glossy_eta", {10, 90}, {70, 45}, {0.03188397f, 0.03188397f, 0.03188397f}},
      {"glossy_eta", {75, 30}, {20, 250}, {0.08421154f, 0.08421154f, 0.08421154f}},
      {"glossy_eta", {45, 0}, {45, 180}, {5.943785f, 5.943785f, 5.943785f}},
      {"spec_trans", {30, 20}, {40, 200}, {0.4224079f, 0.4593702f, 0.348483f}},
      {"spec_trans", {60, 0}, {55, 180}, {1.985543f, 2.115629f, 1.72537f}},
      {"spec_trans", {10, 90}, {70, 45}, {0.0239695f, 0.02692616f, 0.01805616f}},
      {"spec_trans", {75, 30}, {20, 250}, {0.06653778f, 0.07455449f, 0.05050438f}},
      {"spec_trans", {45, 0}, {45, 180}, {1.796965f, 1.941116f, 1.508662f}},
      {"spec_trans", {30, 20}, {160, 200}, {60.16114f, 63.81052f, 52.10108f}},
      {"spec_trans", {50, 0}, {140, 170}, {0.1289997f, 0.1368248f, 0.111717f}},
      {"spec_trans", {150, 10}, {20, 190}, {0.03168537f, 0.0336074f, 0.02744033f}},
      {"spec_trans", {140, 0}, {135, 180}, {5.296346f, 5.296346f, 5.296346f}},
      {"spec_trans", {170, 30}, {120, 200}, {0.001004412f, 0.001004412f, 0.001004412f}},
      {"spec_trans_full_specular", {30, 20}, {40, 200}, {0.0307599f, 0.0307599f, 0.0307599f}},
      {"spec_trans_full_specular", {60, 0}, {55, 180}, {0.1257168f, 0.1257168f, 0.1257168f}},
      {"spec_trans_full_specular", {10, 90}, {70, 45}, {0.0006234078f, 0.0006234078f, 0.0006234078f}},
      {"spec_trans_full_specular", {75, 30}, {20, 250}, {0.00513751f, 0.00513751f, 0.00513751f}},
      {"spec_trans_full_specular", {45, 0}, {45, 180}, {0.05623221f, 0.05623221f, 0.05623221f}},
      {"spec_trans_full_specular", {30, 20}, {160, 200}, {14.42167f, 14.42167f, 14.42167f}},
      {"spec_trans_full_specular", {50, 0}, {140, 170}, {1.434659f, 1.434659f, 1.434659f}},
      {"spec_trans_full_specular", {150, 10}, {20, 190}, {0.2680942f, 0.2680942f, 0.2680942f}},
      {"spec_trans_full_specular", {140, 0}, {135, 180}, {0.1752636f, 0.1752636f, 0.1752636f}},
      {"spec_trans_full_specular", {170, 30}, {120, 200}, {0.003699636f, 0.003699636f, 0.003699636f}},
      {"thin_default", {30, 20}, {40, 200}, {0.1219353f, 0.1219353f, 0.1219353f}},
      {"thin_default", {60, 0}, {55, 180}, {0.09041452f, 0.09041452f, 0.09041452f}},
      {"thin_default", {10, 90}, {70, 45}, {0.05595209f, 0.05595209f, 0.05595209f}},
      {"thin_default", {75, 30}, {20, 250}, {0.1493917f, 0.1493917f, 0.1493917f}},
      {"thin_default", {45, 0}, {45, 180}, {0.1125395f, 0.1125395f, 0.1125395f}},
      {"thin_default", {30, 20}, {160, 200}, {0.0f, 0.0f, 0.0f}},
      {"thin_default", {50, 0}, {140, 170}, {0.0f, 0.0f, 0.0f}},
      {"thin_default", {150, 10}, {20, 190}, {0.0f, 0.0f, 0.0f}},
      {"thin_default", {140, 0}, {135, 180}, {0.1125535f, 0.1125535f, 0.1125535f}},
      {"thin_default", {170, 30}, {120, 200}, {0.08000558f, 0.08000558f, 0.08000558f}},
      {"thin_full", {30, 20}, {40, 200}, {0.0914938f, 0.06175645f, 0.04193155f}},
      {"thin_full", {60, 0}, {55, 180}, {0.2372952f, 0.193911f, 0.1649882f}},
      {"thin_full", {10, 90}, {70, 45}, {0.01812937f, 0.01039147f, 0.005232866f}},
      {"thin_full", {75, 30}, {20, 250}, {0.05336668f, 0.03141138f, 0.01677452f}},
      {"thin_full", {45, 0}, {45, 180}, {0.1426067f, 0.1030101f, 0.07661229f}},
      {"thin_full", {30, 20}, {160, 200}, {1.443918f, 0.8250961f, 0.412548f}},
      {"thin_full", {50, 0}, {140, 170}, {0.4263536f, 0.2436306f, 0.1218153f}},
      {"thin_full", {150, 10}, {20, 190}, {1.679661f, 0.9598064f, 0.4799032f}},
      {"thin_full", {140, 0}, {135, 180}, {0.1225074f, 0.08674455f, 0.06290264f}},
      {"thin_full", {170, 30}, {120, 200}, {0.02741355f, 0.01601371f, 0.008413818f}},
  };
  for (const auto& t : table) {
    const auto s = scene::load_scene(scene("<shape type=\"rectangle\">" + material(t.material) + "</shape>"));
    const scene::Bsdf& bsdf = s.bsdf(s.shapes.at(0));
    const Rgb v = bsdf.eval(scene::Vec2(0.5f), direction(t.wo[0], t.wo[1]), direction(t.wi[0], t.wi[1]));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(v[c], t.rgb[c], 2e-3f * t.rgb[c] + 1e-6f)
          << t.material << " wo (" << t.wo[0] << ", " << t.wo[1] << ") wi (" << t.wi[0] << ", " << t.wi[1]
          << ") channel " << c;
  }
}

TEST_F(Principled, BlackFromBelowWithoutTransmission) {
  const auto s = scene::load_scene(scene("<shape type=\"rectangle\">" + material("coat_sheen_flat") + "</shape>"));
  const scene::Bsdf& bsdf = s.bsdf(s.shapes.at(0));
  EXPECT_EQ(bsdf.eval(scene::Vec2(0.5f), direction(120, 0), direction(130, 180)), Rgb(0.0f));
  EXPECT_EQ(bsdf.eval(scene::Vec2(0.5f), direction(30, 0), direction(130, 180)), Rgb(0.0f));
  EXPECT_FALSE(bsdf.sample(scene::Vec2(0.5f), direction(120, 0), 0.5f, {0.3f, 0.6f}));
}

TEST_F(Principled, RefusesWhatItDoesNotModelByName) {
  EXPECT_THAT(refused(R"(<bsdf type="principled"><float name="spec_trans" value="1.5"/></bsdf>)"),
              ::testing::HasSubstr("spec_trans must lie in [0, 1]"));
  EXPECT_THAT(refused(R"(<bsdf type="principled"><float name="eta" value="1.5"/>
                            <float name="specular" value="0.5"/></bsdf>)"),
              ::testing::HasSubstr("either 'eta' or 'specular'"));
  EXPECT_THAT(refused(R"(<bsdf type="principledthin"><float name="diff_trans" value="2.5"/></bsdf>)"),
              ::testing::HasSubstr("diff_trans must lie in [0, 2]"));
  EXPECT_EQ(refused(R"(<bsdf type="principled"><float name="spec_trans" value="0"/></bsdf>)"), "accepted");
}

// Every value has its range, for a number and for a texture's texels alike (Burley's parameters in [0, 1],
// principledthin's diff_trans in [0, 2]): outside it the scene is refused naming the value, never clamped — a
// roughness of 1e5 made the image ~1e7 too bright as a number and a clamped 1000 as a texture.
TEST_F(Principled, EveryValueHasItsRangeAsANumberAndAsTexels) {
  struct Range {
    const char* bsdf;
    const char* name;
    const char* bound;  // as the message writes it
    float outside;
  };
  const Range ranges[] = {
      {"principled", "roughness", "[0, 1]", 1e5f},       {"principled", "roughness", "[0, 1]", -0.1f},
      {"principled", "sheen", "[0, 1]", 2.0f},           {"principled", "clearcoat", "[0, 1]", 5.0f},
      {"principled", "metallic", "[0, 1]", 1.5f},        {"principled", "anisotropic", "[0, 1]", 2.0f},
      {"principled", "clearcoat_gloss", "[0, 1]", 3.0f}, {"principled", "flatness", "[0, 1]", -1.0f},
      {"principledthin", "roughness", "[0, 1]", 1.5f},   {"principledthin", "sheen", "[0, 1]", 4.0f},
      {"principledthin", "diff_trans", "[0, 2]", 2.5f},  {"principledthin", "sheen_tint", "[0, 1]", 7.0f}};
  for (const Range& r : ranges) {
    const std::string open = std::string("<bsdf type=\"") + r.bsdf + "\">", value = std::to_string(r.outside);
    const std::string number = open + "<float name=\"" + r.name + "\" value=\"" + value + "\"/></bsdf>";
    const std::string texels = open + "<texture name=\"" + r.name +
                               "\" type=\"checkerboard\"><float name=\"color0\" value=\"0.5\"/><float name=\"color1\" "
                               "value=\"" +
                               value + "\"/></texture></bsdf>";
    const std::string constant_texture = open + "<texture name=\"" + r.name +
                                         "\" type=\"rawconstant\"><float name=\"value\" value=\"" + value +
                                         "\"/></texture></bsdf>";
    for (const std::string& xml : {number, texels, constant_texture}) {
      const std::string why = refused(xml);
      EXPECT_THAT(why, ::testing::HasSubstr(std::string(r.name) + " must lie in " + r.bound)) << xml;
    }
  }
  EXPECT_EQ(refused(R"(<bsdf type="principled"><float name="roughness" value="1"/><float name="sheen" value="0"/>
                       <float name="clearcoat" value="1"/></bsdf>)"),
            "accepted")
      << "the bounds themselves are in range";
}

// Every value Mitsuba 3.9.1 takes as a texture (principled: all but eta and specular; principledthin: all, eta
// included) is read at the point: on each cell of a checkerboard the BSDF evaluates, weighs and samples exactly as
// the same BSDF with that cell's value as a constant.
TEST_F(Principled, EveryTexturedValueIsReadAtThePoint) {
  struct Value {
    const char* bsdf;
    const char* name;
    float a, b;
  };
  const Value values[] = {{"principled", "roughness", 0.2f, 0.7f},      {"principled", "anisotropic", 0.1f, 0.8f},
                          {"principled", "metallic", 0.0f, 0.9f},       {"principled", "spec_trans", 0.1f, 0.8f},
                          {"principled", "spec_tint", 0.0f, 1.0f},      {"principled", "sheen", 0.2f, 0.9f},
                          {"principled", "sheen_tint", 0.0f, 1.0f},     {"principled", "flatness", 0.1f, 0.9f},
                          {"principled", "clearcoat", 0.3f, 1.0f},      {"principled", "clearcoat_gloss", 0.1f, 0.9f},
                          {"principledthin", "roughness", 0.2f, 0.7f},  {"principledthin", "anisotropic", 0.1f, 0.8f},
                          {"principledthin", "spec_trans", 0.2f, 0.7f}, {"principledthin", "diff_trans", 0.3f, 1.6f},
                          {"principledthin", "spec_tint", 0.0f, 1.0f},  {"principledthin", "sheen", 0.2f, 0.9f},
                          {"principledthin", "sheen_tint", 0.0f, 1.0f}, {"principledthin", "flatness", 0.1f, 0.9f},
                          {"principledthin", "eta", 1.2f, 1.7f}};
  // The other lobes on, so that each value shows: some transmission, a clearcoat, a sheen, a tint.
  const auto others = [](const Value& v) {
    std::string xml = R"(<rgb name="base_color" value="0.7, 0.4, 0.2"/>)";
    for (const auto& [name, value] : std::vector<std::pair<std::string, const char*>>{{"spec_trans", "0.4"},
                                                                                      {"sheen", "0.5"},
                                                                                      {"sheen_tint", "0.5"},
                                                                                      {"spec_tint", "0.5"},
                                                                                      {"clearcoat", "0.5"},
                                                                                      {"diff_trans", "0.6"},
                                                                                      {"anisotropic", "0.3"}})
      if (name != v.name && (name != "clearcoat" || std::string(v.bsdf) == "principled") &&
          (name != "diff_trans" || std::string(v.bsdf) == "principledthin"))
        xml += R"(<float name=")" + name + R"(" value=")" + value + R"("/>)";
    return xml;
  };
  const scene::TexturePoint cells[2] = {scene::TexturePoint(scene::Vec2(0.25f, 0.25f)),
                                        scene::TexturePoint(scene::Vec2(0.75f, 0.25f))};
  for (const Value& v : values) {
    const std::string open = std::string("<bsdf type=\"") + v.bsdf + "\">" + others(v);
    const auto constant = [&](float x) {
      return open + R"(<float name=")" + v.name + R"(" value=")" + std::to_string(x) + R"("/></bsdf>)";
    };
    const std::string textured = open + R"(<texture name=")" + v.name +
                                 R"(" type="checkerboard"><float name="color0" value=")" + std::to_string(v.a) +
                                 R"("/><float name="color1" value=")" + std::to_string(v.b) + R"("/></texture></bsdf>)";
    const auto s = scene::load_scene(scene("<shape type=\"rectangle\">" + textured + "</shape>" +
                                           "<shape type=\"rectangle\">" + constant(v.a) + "</shape>" +
                                           "<shape type=\"rectangle\">" + constant(v.b) + "</shape>"));
    const scene::Bsdf& t = s.bsdf(s.shapes.at(0));
    const scene::Bsdf* c[2] = {&s.bsdf(s.shapes.at(1)), &s.bsdf(s.shapes.at(2))};
    // Which cell holds color0 is the checkerboard's business (texture_test); the two cells must hold a and b.
    const Vec3 wo = direction(40, 20), wi[] = {direction(55, 200), direction(130, 170), direction(70, 30)};
    const auto same = [&](const scene::Bsdf& want, const scene::TexturePoint& at) {
      for (const Vec3& w : wi)
        if (t.eval(at, wo, w) != want.eval(at, wo, w) || t.pdf(at, wo, w) != want.pdf(at, wo, w)) return false;
      return true;
    };
    const bool first_is_a = same(*c[0], cells[0]);
    for (int cell = 0; cell < 2; ++cell) {
      const scene::Bsdf& want = *c[(cell == 0) == first_is_a ? 0 : 1];
      EXPECT_TRUE(same(want, cells[cell])) << v.bsdf << " " << v.name << " cell " << cell;
      const auto got = t.sample(cells[cell], wo, 0.37f, {0.31f, 0.62f}),
                 expected = want.sample(cells[cell], wo, 0.37f, {0.31f, 0.62f});
      ASSERT_EQ(got.has_value(), expected.has_value()) << v.bsdf << " " << v.name;
      if (got) {
        EXPECT_EQ(got->wi, expected->wi) << v.bsdf << " " << v.name;
      }
    }
    EXPECT_NE(c[0]->eval(cells[0], wo, wi[0]) + c[0]->eval(cells[0], wo, wi[1]) + c[0]->eval(cells[0], wo, wi[2]),
              c[1]->eval(cells[0], wo, wi[0]) + c[1]->eval(cells[0], wo, wi[1]) + c[1]->eval(cells[0], wo, wi[2]))
        << v.bsdf << " " << v.name << ": the two values must differ somewhere for the test to mean anything";
  }
}

}  // namespace
}  // namespace clr::test
