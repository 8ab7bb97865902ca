#include "radiosity/training_lights.hpp"

namespace clr::radiosity {

std::vector<scene::DeltaLight> training_delta_lights(const scene::Scene& scene) {
  std::vector<scene::DeltaLight> lights = scene.delta_lights;
  if (scene.environment)
    if (auto sun = scene.environment->sun_as_directional()) lights.push_back(*sun);
  return lights;
}

geometry::LightSampler training_light_sampler(const scene::Scene& scene) {
  const bool sun = scene.environment && scene.environment->sun_as_directional();
  return geometry::LightSampler(scene, {.delta = false, .environment = !sun});
}

}  // namespace clr::radiosity
