#include "radiosity/radiance_scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "radiosity/training_lights.hpp"

namespace clr::radiosity {

float brightest_emission(const scene::Scene& scene) {
  float brightest = 0;
  for (const auto& shape : scene.shapes) brightest = std::max(brightest, scene::max_component(shape.radiance));
  if (scene.environment) {
    // A Fibonacci sphere of directions: enough to see the level of a map, if not the peak of a small sun, which
    // is all a unit needs (it only has to be right within a few decades).
    constexpr int kDirections = 1024;
    const float golden = float(M_PI) * (3.0f - std::sqrt(5.0f));
    for (int i = 0; i < kDirections; ++i) {
      const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(kDirections), r = std::sqrt(std::max(0.0f, 1 - z * z));
      const float phi = golden * float(i);
      const scene::Vec3 dir(r * std::cos(phi), r * std::sin(phi), z);
      brightest = std::max(brightest, scene::max_component(scene.environment->eval(dir, false)));
    }
  }
  if (const auto lights = training_delta_lights(scene); !lights.empty()) {
    // A delta light has no radiance of its own; what the network learns is the radiance of the surfaces it lights,
    // about ρ/π times the irradiance there. Taken at a typical distance, half the scene's bounding-box diagonal (a
    // unit has to be right within a few decades, not exactly).
    scene::Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const auto& shape : scene.shapes) shape.extend_bounds(lo, hi);
    const float d = 0.5f * glm::length(hi - lo);
    for (const auto& light : lights) {
      float irradiance = scene::max_component(light.intensity);
      if (light.texture) irradiance *= scene::max_component(light.texture->mean());
      if (light.kind != scene::DeltaLight::Kind::directional) irradiance /= d * d;
      if (std::isfinite(irradiance)) brightest = std::max(brightest, irradiance / float(M_PI));
    }
  }
  return std::isfinite(brightest) ? brightest : 0.0f;
}

float radiance_scale(const scene::Scene& scene) {
  const float brightest = brightest_emission(scene);
  if (!(brightest > 0) || (brightest >= kRadianceWindowLow && brightest <= kRadianceWindowHigh)) return 1.0f;
  // Within NetworkConfig::output_scale's range, so that no scene's unit is refused as a config error.
  // The 1e-6 lets an emission written as 1e-4 (the float 0.99999997e-4) be its own decade, not the one below.
  const double decade = std::floor(std::log10(double(brightest)) + 1e-6);
  return float(std::clamp(std::pow(10.0, decade), 1e-30, 1e30));
}

}  // namespace clr::radiosity
