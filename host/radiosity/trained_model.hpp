#pragma once
// A trained N-Module read back from RUN_DIR/model.clr, and its use as the renderer's radiance field.
#include <filesystem>
#include <memory>

#include "nn/network.hpp"
#include "radiosity/renderer.hpp"

namespace clr::radiosity {

// Builds the network the checkpoint was written for and loads its parameters (InputError when the file is
// missing, damaged or of another version).
std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint);

// The I-Module of an ISNR run: its config from RUN_DIR/config.json, its tensors from RUN_DIR/model.clr. InputError
// when the run was trained without one (method nr) or its files are missing or damaged.
std::unique_ptr<nn::Network> load_guide(cl::Context& ctx, const std::filesystem::path& run_dir);

// Host rows in, host RGB out: uploads, infers in the network's chunks, reads back.
RadianceQuery radiance_query(cl::Context& ctx, nn::Network& network);

}  // namespace clr::radiosity
