// The lagged guide's incident half (TrainConfig::guide_lag = 1): the directions a step traces may be drawn a step
// early, from other lobes than the ones its I-Module learns on; p̃ must then be the density of the lobes they were
// drawn from. Drawn ahead or drawn at once, lagged or not, the same sampler lobes give the same samples bit for bit.
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/guide/incident_sampling.hpp"
#include "scene/scene.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

class LaggedSampling : public ClTest {
 protected:
  struct Result {
    std::vector<float> dirs, pdf;
  };
  static Result read(const radiosity::IncidentSampling& s) { return {s.directions.read(), s.pdf.read()}; }
  cl::Buffer<float> random_lobes(std::size_t points, std::uint64_t seed) {
    Pcg32 rng(seed, 9);
    std::vector<float> raw(points * radiosity::kVmfRaw);
    for (auto& x : raw) x = 4.0f * rng.next_float() - 2.0f;
    return cl::Buffer<float>(ctx(), std::span<const float>(raw));
  }
};

TEST_F(LaggedSampling, DensityIsTheDrawingLobesWhicheverLobesLearn) {
  const auto scene = scene::load_scene(std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml");
  const geometry::Geometry geometry(scene);
  radiosity::BatchSettings settings;
  settings.points = 256;
  settings.samples = 4;
  settings.guide = true;
  settings.bsdf_fraction = 0.5f;
  constexpr std::uint64_t seed = 4, step = 3;
  const geometry::SurfaceSampler sampler(scene);
  radiosity::TrainingBatch batch;
  radiosity::sample_training_points(sampler, scene, settings, seed, step, batch);
  const auto drawing = random_lobes(settings.points, 1), learning = random_lobes(settings.points, 2),
             earlier = random_lobes(settings.points, 3);

  // Unlagged: the lobes that draw are the lobes that learn.
  radiosity::IncidentSampling plain(ctx());
  plain.decode(drawing, batch);
  plain.trace(geometry, settings, seed, step, batch);
  plain.upload(settings, batch);
  const Result want = read(plain);
  ASSERT_GT(batch.guided, 0u);

  // Lagged, drawn at once (a session's first step): other lobes learn, the same ones draw.
  radiosity::IncidentSampling at_once(ctx());
  at_once.set_lagged(true);
  at_once.decode(learning, batch);
  at_once.decode_sampling(drawing, batch);
  at_once.trace(geometry, settings, seed, step, batch);
  at_once.upload(settings, batch);
  const Result got_at_once = read(at_once);
  EXPECT_EQ(got_at_once.dirs, want.dirs);
  EXPECT_EQ(got_at_once.pdf, want.pdf);

  // Lagged, drawn ahead during the step before (whose own sampler lobes were others), traced after its advance.
  radiosity::IncidentSampling ahead(ctx());
  ahead.set_lagged(true);
  ahead.decode_sampling(earlier, batch);
  ahead.draw_ahead(drawing, batch, seed, step);
  ahead.advance(step - 1);
  EXPECT_TRUE(ahead.drawn_ahead(step));
  ahead.decode(learning, batch);
  ahead.trace(geometry, settings, seed, step, batch);
  ahead.upload(settings, batch);
  const Result got_ahead = read(ahead);
  EXPECT_EQ(got_ahead.dirs, want.dirs);
  EXPECT_EQ(got_ahead.pdf, want.pdf);

  // The learning lobes' density is another one: the comparisons above can fail.
  radiosity::IncidentSampling other(ctx());
  other.decode(learning, batch);
  other.trace(geometry, settings, seed, step, batch);
  other.upload(settings, batch);
  EXPECT_NE(read(other).pdf, want.pdf);
}

}  // namespace
}  // namespace clr::test
