#include "radiosity/trained_model.hpp"

#include "cl/buffer.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "nn/checkpoint.hpp"

namespace clr::radiosity {
namespace {

// The stored config decides what is allocated on the device; the file must hold the parameters it describes, so a
// damaged or hostile config cannot ask for more memory than the file's own size.
void require_tensors(const nn::Checkpoint& c, const std::string& path, const nn::NetworkConfig& config,
                     const std::string& prefix) {
  for (const auto& [name, count] : {std::pair{"mlp.params", nn::mlp_parameter_count(config)},
                                    std::pair{"grid.table", nn::grid_parameter_count(config)}})
    if (count) c.tensor(path, prefix + name, count);
}

}  // namespace

void require_radiance_network(const nn::NetworkConfig& config) {
  if (config.outputs != 3)
    throw InputError("network.outputs must be 3 (the N-Module's RGB radiance), got " + std::to_string(config.outputs));
}

std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint, bool to_train) {
  const nn::Checkpoint c = nn::read_checkpoint(checkpoint.string());
  const nlohmann::json config = parse_json(c.config_json, "the network config of checkpoint " + checkpoint.string());
  nn::NetworkConfig network_config;
  try {
    network_config = nn::network_config_from_json(config);
    require_radiance_network(network_config);
    require_tensors(c, checkpoint.string(), network_config, "");
  } catch (const InputError& e) {
    const std::string what = e.what(), prefix = "checkpoint " + checkpoint.string();
    throw InputError(what.starts_with(prefix) ? what : prefix + ": " + what);
  }
  auto network = std::make_unique<nn::Network>(ctx, network_config);
  network->load(checkpoint.string());
  if (!to_train) network->adopt_average();
  return network;
}

std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint,
                                          const nn::NetworkConfig& config, const std::string& prefix) {
  const nn::Checkpoint c = nn::read_checkpoint(checkpoint.string());
  require_tensors(c, checkpoint.string(), config, prefix);
  auto network = std::make_unique<nn::Network>(ctx, config);
  network->restore(c, checkpoint.string(), prefix);
  return network;
}

RadianceQuery radiance_query(cl::Context& ctx, nn::Network& network) {
  // Buffers shared by every call and grown on demand: rendering calls this once per chunk of image lines.
  struct State {
    cl::Buffer<float> rows, rgb;
  };
  auto state = std::make_shared<State>();
  return [&ctx, &network, state](std::span<const float> rows, std::span<float> rgb) {
    const std::size_t n = rows.size() / nn::kRawInputs;
    if (state->rows.size() < rows.size()) state->rows = cl::Buffer<float>(ctx, rows.size());
    if (state->rgb.size() < n * 3) state->rgb = cl::Buffer<float>(ctx, n * 3);
    state->rows.write(rows);
    network.infer(state->rows, n, state->rgb);
    state->rgb.read(rgb.first(n * 3));
  };
}

}  // namespace clr::radiosity
