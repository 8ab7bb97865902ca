#pragma once
// `clradiosity export`: a run's model.clr as a safetensors file (nn/safetensors.hpp) that PyTorch, JAX or numpy
// open without clradiosity. Every tensor of the checkpoint is named (the N-Module's without a prefix, the I-Module's
// under "guide.", the lagged guide's copy under "guide_before.", split per layer and level by nn/export.hpp), and
// the metadata carries what evaluating them needs (docs/cli.md, "export").
#include <filesystem>

#include "nn/safetensors.hpp"

namespace clr::radiosity {

// `run`: a run directory, or a model.clr whose folder holds the run's config.json (needed for the I-Module's
// config). Reads only; InputError naming the file at fault when the run is missing, damaged or inconsistent.
// Without `optimizer_state` the Adam moments are left out.
nn::SafeTensors export_model(const std::filesystem::path& run, bool optimizer_state);

}  // namespace clr::radiosity
