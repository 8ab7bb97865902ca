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

// The budget presets' names, in order of budget: preview, balanced, quality (the main job's choices).
const std::vector<std::string>& budget_preset_names();
// Every preset `train` knows: the budget presets and `paper`.
const std::vector<std::string>& preset_names();

// `paper`: the ISNR paper's settings as far as it states them (§4.3, §5.1; docs/presets.md): the N-Module 512 wide,
// N = 4 (Table 1; --samples 32 for Table 2), Adam at 5e-3 for both modules, the multiresolution hash grid of the
// work it cites (Müller et al. 2022), and a step budget of Table 1 where none is given; what it leaves open (the
// batch among them) is chosen and said. On every device: the paper's settings are a GPU's.
inline constexpr const char* kPaperPreset = "paper";

// Applies preset `name` to `config` (its `network` overrides gain the width and the table size; `paper` also the
// grid and the learning rates) and returns one line per choice saying what and why. InputError for an unknown name.
std::vector<std::string> apply_preset(const std::string& name, TrainConfig& config, const SceneInputs& scene,
                                      const cl::DeviceInfo& device);

}  // namespace clr::radiosity
