// ISNR on one scene per delta emitter kind (scenes/delta-lights/: the Cornell room lit by a point, a spot, a
// projector or, through its open top, a directional light), trained with the default settings for the same number
// of steps as the bundled Cornell box and measured the same way; and the principled BSDF (scenes/principled.xml), the
// exact cylinder and disk (scenes/exact-shapes.xml) and a sunsky (scenes/sunsky.xml, its sun taken as a directional
// light) (MAPE of a 64×64 render against the path tracer). "Comparable to the Cornell box" is held as at most twice
// its MAPE: a scene whose delta light the right-hand side missed renders black (MAPE near 1), one that learned only the
// direct term loses the indirect half of the room. The yardstick is the box trained without next-event estimation
// (its light found by the directions alone, as when the bound was set): with it the box reaches about half that MAPE,
// below what a point light's hard shadows allow at these steps, though the point light's direct term is exact either
// way (measured: box 0.085 without NEE, 0.061 with it; point 0.132, exact shapes 0.124, spot 0.099; docs/method.md).
#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/renderer.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
const fs::path kScenes = fs::path(CLR_SOURCE_DIR) / "scenes";
constexpr long kSteps = 600;  // a few minutes a scene on a 2-core CPU

struct Result {
  double mape;
  std::size_t non_finite;
};

class DeltaLightTrainingSlow : public ClTest {
 protected:
  Result train_and_measure(const fs::path& file, bool nee = true) {
    const auto scene = scene::load_scene(file, {{"res", "64"}});
    const geometry::Geometry geometry(scene);
    reference::RenderOptions ref_options;
    ref_options.spp = 1024;
    const auto ref = reference::render(geometry, ref_options);
    const fs::path run = fs::temp_directory_path() / ("clr_delta_slow_" + std::to_string(::getpid()));
    fs::remove_all(run);
    radiosity::TrainConfig config;  // ISNR, the defaults
    config.steps = kSteps;
    config.nee = nee;
    config.log_every = 1000000;
    config.checkpoint_every = 1000000;
    radiosity::Trainer trainer(ctx(), geometry, config, run, false);
    trainer.run();
    fs::remove_all(run);
    const radiosity::RenderSettings settings{.width = 64, .height = 64, .spp = 4};
    const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx(), trainer.network()), settings);
    const auto m = image::compare(img, ref);
    std::cout << file.filename().string() << ": ISNR " << kSteps << " steps, NEE " << (nee ? "on" : "off") << ", MAPE "
              << m.mape << ", non-finite " << m.non_finite << "\n";
    return {m.mape, m.non_finite};
  }
};

TEST_F(DeltaLightTrainingSlow, EachKindTrainsAsWellAsTheCornellBox) {
  const Result cornell = train_and_measure(kScenes / "cornell-box.xml", false);
  ASSERT_EQ(cornell.non_finite, 0u);
  RecordProperty("cornell_mape", std::to_string(cornell.mape));
  for (const char* kind : {"point", "spot", "projector", "directional"}) {
    const Result r = train_and_measure(kScenes / "delta-lights" / (std::string(kind) + ".xml"));
    RecordProperty(std::string(kind) + "_mape", std::to_string(r.mape));
    EXPECT_EQ(r.non_finite, 0u) << kind;
    EXPECT_LT(r.mape, 2.0 * cornell.mape) << kind << " against the Cornell box's " << cornell.mape;
  }
  // The principled BSDF's lobes (a clear-coated metal, a rough glass, a sheened diffuse) in the same room, lit as
  // the Cornell box is.
  const Result principled = train_and_measure(kScenes / "principled.xml");
  RecordProperty("principled_mape", std::to_string(principled.mape));
  EXPECT_EQ(principled.non_finite, 0u);
  EXPECT_LT(principled.mape, 2.0 * cornell.mape) << "principled against the Cornell box's " << cornell.mape;
  // A tube light, a textured oval (a stretched disk) and a textured pillar: exact shapes as emitter and receivers.
  const Result exact = train_and_measure(kScenes / "exact-shapes.xml");
  RecordProperty("exact_shapes_mape", std::to_string(exact.mape));
  EXPECT_EQ(exact.non_finite, 0u);
  EXPECT_LT(exact.mape, 2.0 * cornell.mape) << "exact shapes against the Cornell box's " << cornell.mape;
  // Hosek–Wilkie sky and sun over a courtyard: the sun's 0.27° disc, 10⁵ times the sky, reached by next-event
  // estimation (a sun met only by chance left a MAPE of 0.34 at these steps).
  const Result sunsky = train_and_measure(kScenes / "sunsky.xml");
  RecordProperty("sunsky_mape", std::to_string(sunsky.mape));
  EXPECT_EQ(sunsky.non_finite, 0u);
  EXPECT_LT(sunsky.mape, 2.0 * cornell.mape) << "sunsky against the Cornell box's " << cornell.mape;
}

}  // namespace
}  // namespace clr::test
