// Next-event estimation in the training's right-hand side (TrainConfig::nee): a light sample beside each direction,
// MIS-weighted against the BSDF's density, and the emission the directions hit weighted by the complement. The
// directions (and so the lookups' weights) are the same with and without it; what changes is how the emission is
// estimated. Checked at fixed points, host side: with and without NEE the estimate of the light a point reflects
// agrees in the mean (area lights, a sphere light drawn by its cone, an environment map, a mixture with a delta light
// and a glass in front of the light), and its variance falls where emitters are small.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "../scene/scene_files.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/training_batch.hpp"
#include "radiosity/training_lights.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

// Per point, the S-sample estimates of the light it reflects towards ω_o from emission alone (the lookups' part,
// w·L, is the same sum either way), and their sample variance, averaged over the RGB channels.
struct Estimates {
  std::vector<double> mean, variance;
};

Estimates emission_estimates(const geometry::Geometry& g, std::size_t points, std::size_t samples, bool nee,
                             std::uint64_t seed) {
  const geometry::SurfaceSampler sampler(g.scene());
  radiosity::BatchSettings settings;
  settings.points = points;
  settings.samples = samples;
  settings.next_event = nee;
  radiosity::TrainingBatch batch;
  radiosity::sample_training_points(sampler, g.scene(), settings, seed, 0, batch);
  const geometry::LightSampler lights = radiosity::training_light_sampler(g.scene());
  radiosity::trace_incident(g, settings, seed, 0, {}, batch, nee ? &lights : nullptr);
  EXPECT_EQ(batch.light.empty(), !nee || lights.empty());
  Estimates e;
  for (std::size_t m = 0; m < points; ++m) {
    double mean = 0, variance = 0;
    for (int ch = 0; ch < 3; ++ch) {
      // Delta lights are a constant per point, in `direct` beside the light samples' mean.
      double light_mean = 0;
      for (std::size_t n = 0; n < samples; ++n)
        if (!batch.light.empty()) light_mean += batch.light[3 * (m * samples + n) + ch] / double(samples);
      const double constant = batch.direct.empty() ? 0.0 : batch.direct[3 * m + ch] - light_mean;
      double s1 = 0, s2 = 0;
      for (std::size_t n = 0; n < samples; ++n) {
        const std::size_t s = m * samples + n;
        double term = batch.emitted[3 * s + ch] / batch.pdf[s];
        if (!batch.light.empty()) term += batch.light[3 * s + ch];
        s1 += term;
        s2 += term * term;
      }
      const double mu = s1 / double(samples);
      mean += (mu + constant) / 3;
      variance += std::max(0.0, s2 / double(samples) - mu * mu) / 3;
    }
    e.mean.push_back(mean);
    e.variance.push_back(variance);
  }
  return e;
}

class NextEventRhs : public SceneFiles {
 protected:
  // Compares the two estimators over the same points: the mean over points of the per-point difference, in units of
  // its standard error (the points' own spread), and returns variance(off) / variance(on), summed over points.
  double compare(const fs::path& file, std::size_t points = 256, std::size_t samples = 256) {
    const auto s = scene::load_scene(file);
    const geometry::Geometry g(s);
    const Estimates off = emission_estimates(g, points, samples, false, 5),
                    on = emission_estimates(g, points, samples, true, 5);
    double d1 = 0, d2 = 0, level = 0, var_off = 0, var_on = 0;
    for (std::size_t m = 0; m < points; ++m) {
      const double d = on.mean[m] - off.mean[m];
      d1 += d;
      d2 += d * d;
      level += off.mean[m];
      var_off += off.variance[m];
      var_on += on.variance[m];
    }
    const double n = double(points), mean = d1 / n, se = std::sqrt(std::max(0.0, d2 / n - mean * mean) / (n - 1));
    EXPECT_GT(level, 0.0) << "the points see no light: the test would show nothing";
    EXPECT_LE(std::fabs(mean), 4 * se + 1e-6 * level / n)
        << "NEE on and off disagree: mean difference " << mean << " ± " << se << " (level " << level / n << ")";
    return var_off / std::max(var_on, 1e-300);
  }
};

constexpr const char* kBox = R"(
    <shape type="cube"><boolean name="flip_normals" value="true"/><transform name="to_world"><scale value="2"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.4"/><translate x="0.3" z="-1.2"/></transform>
      <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></shape>)";

TEST_F(NextEventRhs, SmallAreaLightAgreesAndIsLessNoisy) {
  // A small ceiling light in a closed box with a rough metal block: BSDF sampling finds it rarely.
  const double gain = compare(scene(std::string(kBox) + R"(
    <shape type="rectangle"><transform name="to_world"><scale value="0.2"/><rotate x="1" angle="180"/>
      <translate z="1.99"/></transform><emitter type="area"><rgb name="radiance" value="40, 30, 20"/></emitter></shape>)"));
  EXPECT_GT(gain, 4.0) << "next-event estimation should cut the variance of a small light's estimate";
}

TEST_F(NextEventRhs, SphereLightDrawnByItsConeAgrees) {
  // A sphere light is drawn by the cone it subtends (LightSampler): its density must match the MIS weight's.
  const double gain = compare(scene(std::string(kBox) + R"(
    <shape type="sphere"><point name="center" value="-0.5, 0.4, 1.2"/><float name="radius" value="0.15"/>
      <emitter type="area"><rgb name="radiance" value="30"/></emitter></shape>)"));
  EXPECT_GT(gain, 2.0);
}

TEST_F(NextEventRhs, EnvironmentMapAgrees) {
  // An open floor with a wall under a map with a bright patch: the map's importance sampling against BSDF sampling.
  image::Image map(32, 16);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const float patch = (x >= 20 && x <= 21 && y >= 4 && y <= 5) ? 200.0f : 0.0f;
      for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = 0.2f + 0.01f * float(x + c) + patch;
    }
  image::write_exr(dir_ / "map.exr", map);
  const double gain = compare(scene(R"(
    <emitter type="envmap"><string name="filename" value="map.exr"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="cube"><transform name="to_world"><scale x="0.1" y="1" z="1"/><translate z="1"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>)"));
  EXPECT_GT(gain, 2.0);
}

TEST_F(NextEventRhs, MixtureWithADeltaLightAndGlassAgrees) {
  // Every kind at once: an area light, a sphere light behind a glass pane (its light through the glass reaches the
  // points only by sampled directions, at full weight: a shadow ray stops at the glass), a point light (summed whole,
  // in `direct`, either way) and a constant environment seen through an opening.
  compare(scene(R"(
    <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
    <emitter type="point"><point name="position" value="0.5, -0.5, 0.5"/><rgb name="intensity" value="2"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/></transform>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.3"/><rotate x="1" angle="180"/>
      <translate x="-1" z="1.5"/></transform><emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
    <shape type="sphere"><point name="center" value="1, 1, 1"/><float name="radius" value="0.2"/>
      <emitter type="area"><rgb name="radiance" value="20"/></emitter></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.8"/><rotate y="1" angle="90"/>
      <translate x="0.6" y="0.6" z="0.8"/></transform><bsdf type="dielectric"/></shape>)"));
}

TEST_F(NextEventRhs, CornellBoxAgrees) {
  // The bundled scene, whose light is a small rectangle under the ceiling.
  EXPECT_GT(compare(fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml", 128, 128), 2.0);
}

TEST_F(NextEventRhs, SunskyTakesTheSunWholeAndTheSkyByDirections) {
  // A sun taken as a directional light (in `direct`): the sampler then draws no environment — drawing the sky would
  // draw the sun's cone too, counting it twice — and the directions see the sky at full weight.
  const auto s = scene::load_scene(fs::path(CLR_SOURCE_DIR) / "scenes" / "sunsky.xml");
  ASSERT_TRUE(s.environment && s.environment->sun_as_directional());
  const geometry::LightSampler lights = radiosity::training_light_sampler(s);
  EXPECT_TRUE(lights.empty());
  EXPECT_EQ(lights.pdf_environment(scene::Vec3(0, 1, 0)), 0.0f);
  const geometry::LightSampler reference(s);  // the path tracer's draws it
  EXPECT_GT(reference.pdf_environment(scene::Vec3(0, 1, 0)), 0.0f);
  compare(fs::path(CLR_SOURCE_DIR) / "scenes" / "sunsky.xml", 64, 64);
}

}  // namespace
}  // namespace clr::test
