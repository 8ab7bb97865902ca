#pragma once
// The lights training takes by next-event estimation, each point's direct term added to its right-hand side
// (docs/scenes.md, "Delta lights in training"): the scene's delta lights, and a sunsky's sun as a directional light of
// its irradiance (its 0.27° disc, ~10⁵ times the sky, is beyond what directions drawn at random find).
#include <vector>

#include "scene/scene.hpp"

namespace clr::radiosity {

std::vector<scene::DeltaLight> training_delta_lights(const scene::Scene& scene);

}  // namespace clr::radiosity
