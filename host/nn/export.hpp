#pragma once
// One network of a checkpoint as tensors others can evaluate (`clradiosity export`, docs/cli.md): the MLP's flat
// parameter buffer split into per-layer weights ([outputs × inputs], PyTorch's nn.Linear layout, the transpose of
// the engine's) and biases, the hash-grid table into one [entries × features] tensor per level, and the Adam moments
// split the same way; and a JSON description of everything needed to evaluate it from a raw input row.
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "nn/checkpoint.hpp"
#include "nn/network.hpp"
#include "nn/safetensors.hpp"

namespace clr::nn {

// Appends the tensors the checkpoint holds under `prefix` (mlp.params, grid.table, their Adam moments where present
// and `optimizer_state` is set) as `prefix` + "mlp.layers.L.weight" / ".bias", "grid.levels.L", and
// "adam.m." / "adam.v." + those names. Records each checkpoint tensor it took in `taken`. InputError naming
// `path` when a tensor's size does not match `config`.
void add_network_tensors(const Checkpoint& c, const std::string& path, const NetworkConfig& config,
                         const std::string& prefix, bool optimizer_state, SafeTensors& out,
                         std::set<std::string>& taken);

// What a reader needs to evaluate the network named by `prefix`: the raw input row's columns, each encoding part
// with its columns and rule (the hash grid's levels, box, hashing and interpolation; the SH convention), the
// layers with their tensors and activations, the output scale, and the config itself.
nlohmann::ordered_json describe_network(const NetworkConfig& config, const std::string& prefix);

}  // namespace clr::nn
