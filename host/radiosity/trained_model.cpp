#include "radiosity/trained_model.hpp"

#include <fstream>

#include "cl/buffer.hpp"
#include "common/error.hpp"
#include "nn/checkpoint.hpp"

namespace clr::radiosity {

std::unique_ptr<nn::Network> load_network(cl::Context& ctx, const std::filesystem::path& checkpoint) {
  const nn::Checkpoint c = nn::read_checkpoint(checkpoint.string());
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(c.config_json);
  } catch (const nlohmann::json::exception& e) {
    throw InputError("checkpoint " + checkpoint.string() + ": malformed network config: " + e.what());
  }
  auto network = std::make_unique<nn::Network>(ctx, nn::network_config_from_json(config));
  network->load(checkpoint.string());
  return network;
}

std::unique_ptr<nn::Network> load_guide(cl::Context& ctx, const std::filesystem::path& run_dir) {
  const auto config_path = run_dir / "config.json";
  std::ifstream in(config_path);
  if (!in) throw InputError("cannot read " + config_path.string());
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError("malformed JSON in " + config_path.string() + ": " + e.what());
  }
  if (config.value("method", "nr") != "isnr" || !config.contains("guide"))
    throw InputError(run_dir.string() + " was trained without an I-Module (method nr): there is no guide to read");
  auto guide = std::make_unique<nn::Network>(ctx, nn::network_config_from_json(config.at("guide")));
  const auto model = (run_dir / "model.clr").string();
  guide->restore(nn::read_checkpoint(model), model, "guide.");
  return guide;
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
