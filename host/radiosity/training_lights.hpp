#pragma once
// The lights training takes by next-event estimation, each point's direct term added to its right-hand side
// (docs/scenes.md, "Delta lights in training"): the scene's delta lights, and a sunsky's sun as a directional light of
// its irradiance (its 0.27° disc, ~10⁵ times the sky, is beyond what directions drawn at random find).
#include <vector>

#include "geometry/light_sampler.hpp"
#include "scene/scene.hpp"

namespace clr::radiosity {

std::vector<scene::DeltaLight> training_delta_lights(const scene::Scene& scene);

// The light sampler of the right-hand side's next-event estimation (TrainConfig::nee): the path tracer's, without
// the lights above — they are summed whole — and without an environment whose sun is among them (its sky is then
// found by the sampled directions, as the sun-less segment of trace_to_surface sees it).
geometry::LightSampler training_light_sampler(const scene::Scene& scene);

}  // namespace clr::radiosity
