// White furnaces (issue 37): an object whose BSDF loses no energy, alone in a uniform environment of radiance 1,
// shows exactly 1 in every direction: whatever enters leaves again. One case per lossless BSDF plugin and form
// (sides, blends, masks, textures, IORs), each on a sphere and on a cube, so that a BSDF that traps or loses light
// (a thin sheet that reflects totally from its back side, a lobe dropped on one side) is caught here. The path
// tracer renders them unbounded (roulette keeps it unbiased), so the image's mean must be 1 within its noise.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "geometry/geometry.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

struct Furnace {
  const char* name;
  const char* bsdf;
  // What the model itself may lose, beyond the noise: single-scattering microfacets lose the light that would
  // bounce between facets, a fraction that grows with roughness and with the internal bounces of a closed shape (at α =
  // 0.02, GGX, 0.6 % in the cube, as Mitsuba 3 loses too).
  double model_loss = 0;
};

constexpr const char* kMirror = R"(<bsdf type="conductor"><string name="material" value="none"/></bsdf>)";
constexpr const char* kWhite = R"(<bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>)";
// A texture that is 1 everywhere, by way of the texture code (two equal squares).
constexpr const char* kOne =
    R"(<texture type="checkerboard" name="%s"><rgb name="color0" value="1"/><rgb name="color1" value="1"/></texture>)";

std::string with_texture(const std::string& open, const std::string& name, const std::string& close) {
  std::string t = kOne;
  t.replace(t.find("%s"), 2, name);
  return open + t + close;
}

std::vector<Furnace> furnaces() {
  static const std::string textured_diffuse = with_texture(R"(<bsdf type="diffuse">)", "reflectance", "</bsdf>");
  static const std::string textured_thin =
      with_texture(R"(<bsdf type="thindielectric">)", "specular_transmittance", "</bsdf>");
  static const std::string textured_glass =
      with_texture(R"(<bsdf type="dielectric">)", "specular_reflectance", "</bsdf>");
  static const std::string two_sided_mirror = std::string(R"(<bsdf type="twosided">)") + kMirror + "</bsdf>";
  static const std::string two_sided_white = std::string(R"(<bsdf type="twosided">)") + kWhite + "</bsdf>";
  static const std::string blend_white_mirror =
      std::string(R"(<bsdf type="blendbsdf"><float name="weight" value="0.3"/>)") + kWhite + kMirror + "</bsdf>";
  // Blends of BSDFs that agree on the medium behind the surface (two sheets; a sheet and a two-sided mirror): a
  // blend of a glass and a sheet has no consistent inside, and a one-sided BSDF is black from within a closed shape.
  static const std::string blend_sheets =
      R"(<bsdf type="blendbsdf"><float name="weight" value="0.6"/><bsdf type="thindielectric"/><bsdf type="thindielectric"><float name="int_ior" value="2.4"/></bsdf></bsdf>)";
  static const std::string blend_sheet_mirror =
      std::string(R"(<bsdf type="blendbsdf"><float name="weight" value="0.4"/><bsdf type="thindielectric"/>)") +
      two_sided_mirror + "</bsdf>";
  static const std::string mask_glass =
      R"(<bsdf type="mask"><float name="opacity" value="0.4"/><bsdf type="dielectric"/></bsdf>)";
  static const std::string mask_white =
      std::string(R"(<bsdf type="mask"><float name="opacity" value="0.7"/>)") + two_sided_white + "</bsdf>";
  return {
      {"diffuse", kWhite},
      {"diffuse_textured", textured_diffuse.c_str()},
      {"twosided_diffuse", two_sided_white.c_str()},
      {"conductor", kMirror},
      {"twosided_conductor", two_sided_mirror.c_str()},
      {"roughconductor",
       R"(<bsdf type="roughconductor"><string name="material" value="none"/><float name="alpha" value="0.02"/></bsdf>)",
       0.01},
      {"dielectric", R"(<bsdf type="dielectric"/>)"},
      {"dielectric_water_in_oil",
       R"(<bsdf type="dielectric"><float name="int_ior" value="1.33"/><float name="ext_ior" value="1.47"/></bsdf>)"},
      {"dielectric_textured", textured_glass.c_str()},
      {"thindielectric", R"(<bsdf type="thindielectric"/>)"},
      {"thindielectric_diamond", R"(<bsdf type="thindielectric"><float name="int_ior" value="2.4"/></bsdf>)"},
      {"thindielectric_textured", textured_thin.c_str()},
      {"roughdielectric_beckmann", R"(<bsdf type="roughdielectric"><float name="alpha" value="0.02"/></bsdf>)", 0.01},
      {"roughdielectric_textured",
       R"(<bsdf type="roughdielectric"><texture type="checkerboard" name="alpha"><rgb name="color0" value="0.01"/><rgb name="color1" value="0.03"/></texture></bsdf>)",
       0.01},
      {"roughdielectric_ggx",
       R"(<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.02"/></bsdf>)",
       0.01},
      {"plastic", R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="1"/></bsdf>)"},
      {"roughplastic",
       R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="1"/><float name="alpha" value="0.02"/></bsdf>)",
       0.01},
      {"blendbsdf_diffuse_conductor", blend_white_mirror.c_str()},
      {"blendbsdf_sheets", blend_sheets.c_str()},
      {"blendbsdf_sheet_mirror", blend_sheet_mirror.c_str()},
      {"mask_dielectric", mask_glass.c_str()},
      {"mask_twosided_diffuse", mask_white.c_str()},
      {"null", R"(<bsdf type="null"/>)"},
  };
}

class WhiteFurnace : public SceneFiles, public ::testing::WithParamInterface<std::tuple<std::string, Furnace>> {};

TEST_P(WhiteFurnace, ShowsTheEnvironmentExactly) {
  const auto& [shape, furnace] = GetParam();
  const auto path = scene(R"(
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0.3, 0.5, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
  <shape type=")" + shape +
                          R"(">)" + furnace.bsdf + "</shape>");
  const auto s = scene::load_scene(path);
  const geometry::Geometry geometry(s);
  reference::RenderOptions opt;
  opt.spp = 256;
  opt.seed = 7;
  const auto img = reference::render(geometry, opt);
  // The noise: the spread of the pixel means over their count (pixels are independent; the samples within one are
  // averaged already).
  double sum = 0, sum2 = 0;
  for (float v : img.rgb) {
    sum += v;
    sum2 += double(v) * v;
  }
  const double n = double(img.rgb.size()) / 3.0;  // the channels of one pixel share their paths
  const double mean = sum / double(img.rgb.size()),
               spread = std::sqrt(std::max(0.0, sum2 / double(img.rgb.size()) - mean * mean));
  const double bound = 5.0 * spread / std::sqrt(n) + 1e-4;
  std::cout << shape << " " << furnace.name << ": mean " << mean << " (noise bound " << bound << ", model loss up to "
            << furnace.model_loss << ")\n";
  EXPECT_LT(mean, 1.0 + bound);
  EXPECT_GT(mean, 1.0 - bound - furnace.model_loss);
}

INSTANTIATE_TEST_SUITE_P(EveryLosslessBsdf, WhiteFurnace,
                         ::testing::Combine(::testing::Values("sphere", "cube"), ::testing::ValuesIn(furnaces())),
                         [](const auto& param_info) {
                           return std::get<0>(param_info.param) + "_" + std::get<1>(param_info.param).name;
                         });

}  // namespace
}  // namespace clr::test
