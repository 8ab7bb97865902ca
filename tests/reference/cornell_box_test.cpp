// The Cornell box of ../shared/scenes against Tungsten's independent render of it.
#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/geometry.hpp"
#include "reference/agreement.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/shared_scenes.hpp"

namespace clr::test {
namespace {

TEST(CornellBox, AgreesWithTungsten) {
  const std::filesystem::path dir = clr::test::shared_scenes() / "cornell-box";
  CLR_REQUIRE_SHARED(dir / "scene.xml");
  const auto scene = scene::load_scene(dir / "scene.xml");
  const geometry::Geometry geometry(scene);
  reference::RenderOptions opt;
  opt.width = opt.height = 128;
  // 256 spp: the image mean's noise is ~0.1 %, a block's ~1 %, both well inside the 1 % and 2 % bounds.
  opt.spp = 256;
  // Tungsten rendered the whole transport; the file's integrator (an aov over `direct`) asks for one bounce.
  opt.max_depth = reference::kWholeTransport;
  const auto img = reference::render(geometry, opt);
  const auto ref = image::match_size(image::read_exr(dir / "TungstenRender.exr"), img);
  const Agreement a = agreement(img, ref);
  RecordProperty("agreement", ::testing::PrintToString(a));
  std::cout << "Cornell box 128x128, 256 spp: " << a << "\n";
  EXPECT_LT(a.worst_mean_error, 0.01) << a;
  EXPECT_LT(a.median_block_error, 0.02) << a;
}

}  // namespace
}  // namespace clr::test
