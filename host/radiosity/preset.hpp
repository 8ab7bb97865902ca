#pragma once
// Budget presets (`--preset preview|balanced|quality` on `train` and the main job): settings picked from the
// measured speed/accuracy curves (docs/presets.md) for a budget class, the scene and the device. A preset sets
// the batch, the samples per point N, the N-Module's width and its hash-table size, and the budget when none is
// given; flags given beside it override its choices.
#include <string>
#include <vector>

#include "cl/device.hpp"
#include "radiosity/scene_inputs.hpp"
#include "radiosity/train_config.hpp"

namespace clr::radiosity {

// The presets' names, in order of budget: preview, balanced, quality.
const std::vector<std::string>& preset_names();

// Applies preset `name` to `config` (its `network` overrides gain the width and the table size) and returns one
// line per choice saying what and why. InputError for an unknown name.
std::vector<std::string> apply_preset(const std::string& name, TrainConfig& config, const SceneInputs& scene,
                                      const cl::DeviceInfo& device);

}  // namespace clr::radiosity
