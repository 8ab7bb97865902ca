#pragma once
// A trained N-Module read back from RUN_DIR/model.clr, and its use as the renderer's radiance field.
#include <filesystem>
#include <memory>

#include "nn/network.hpp"
#include "radiosity/renderer.hpp"

namespace clr::radiosity {

// The N-Module's shape, which its users assume: 3 outputs (RGB radiance). InputError naming the setting otherwise;
// checked where one is made (network settings) and where one is read (a checkpoint), so that neither can reach the
// device with another shape.
void require_radiance_network(const nn::NetworkConfig& config);

// Builds the network the checkpoint was written for and loads its parameters (InputError when the file is
// missing, damaged or of another version). The model to render is the weight average where the run kept one
// (TrainConfig::average_steps); `to_train` keeps the parameters and the average apart, as training resumes them.
std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint,
                                          bool to_train = false);

// A network of `config` whose tensors are stored under `prefix` in the checkpoint (the I-Module's, beside the
// N-Module's; run_directory.hpp reads its config from the run).
std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint,
                                          const nn::NetworkConfig& config, const std::string& prefix);

// Host rows in, host RGB out: uploads, infers in the network's chunks, reads back.
RadianceQuery radiance_query(cl::Context& ctx, nn::Network& network);

}  // namespace clr::radiosity
