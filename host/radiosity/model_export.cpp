#include "radiosity/model_export.hpp"

#include <nlohmann/json.hpp>
#include <set>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "nn/checkpoint.hpp"
#include "nn/export.hpp"
#include "nn/network.hpp"
#include "radiosity/run_directory.hpp"

namespace clr::radiosity {
namespace fs = std::filesystem;

namespace {

// A config from JSON, its faults named with `where`.
nn::NetworkConfig network_config(const nlohmann::json& j, const std::string& where) {
  try {
    return nn::network_config_from_json(j);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
}

}  // namespace

nn::SafeTensors export_model(const fs::path& run, bool optimizer_state) {
  if (!fs::exists(run)) throw InputError("run " + run.string() + " not found");
  const fs::path model = fs::is_directory(run) ? RunDirectory::model_path(run) : run;
  const fs::path dir = fs::is_directory(run) ? run : run.parent_path();
  nn::Checkpoint c = nn::read_checkpoint(model.string());
  const std::string file = model.string();
  // A run with a weight average renders the average (TrainConfig::average_steps): the N-Module exported is that
  // model, and the parameters training would resume from follow flat, as "training.mlp.params" and
  // "training.grid.table" (not with --weights-only).
  const bool averaged = c.has("mlp.average");
  if (averaged)
    for (auto& [name, values] : c.tensors) {
      if (name == "mlp.params" || name == "grid.table")
        name = "training." + name;
      else if (name == "mlp.average")
        name = "mlp.params";
      else if (name == "grid.average")
        name = "grid.table";
    }
  const nn::NetworkConfig radiance =
      network_config(parse_json(c.config_json, "the network config of checkpoint " + file), "checkpoint " + file);

  // The run's own settings: the I-Module's config lives there, not in the checkpoint.
  nlohmann::json settings;
  if (fs::exists(RunDirectory::config_path(dir)))
    settings = read_json_file(RunDirectory::config_path(dir), "run config");
  const bool guided = c.has("guide.mlp.params");
  std::optional<nn::NetworkConfig> guide;
  if (guided) {
    if (!settings.is_object() || !settings.contains("guide"))
      throw InputError("checkpoint " + file + " holds an I-Module, but " + RunDirectory::config_path(dir).string() +
                       " (its config) is missing or has no 'guide'");
    guide = network_config(settings.at("guide"), RunDirectory::config_path(dir).string() + ": guide");
  }

  nn::SafeTensors out;
  std::set<std::string> taken;
  nlohmann::ordered_json networks = nlohmann::ordered_json::object();
  nn::add_network_tensors(c, file, radiance, "", optimizer_state, out, taken);
  // The trained parameters behind an average are training state, as the moments are: not weights.
  if (averaged && !optimizer_state)
    for (const char* name : {"training.mlp.params", "training.grid.table"}) taken.insert(name);
  networks["n_module"] = nn::describe_network(radiance, "");
  if (guide) {
    nn::add_network_tensors(c, file, *guide, "guide.", optimizer_state, out, taken);
    networks["i_module"] = nn::describe_network(*guide, "guide.");
    if (c.has("guide_before.mlp.params")) {
      // Parameters only: the copy is evaluated, never trained (radiosity/trainer.hpp's lagged guide).
      nn::add_network_tensors(c, file, *guide, "guide_before.", false, out, taken);
      networks["i_module_before_update"] = nn::describe_network(*guide, "guide_before.");
    }
  }
  // A tensor of a kind this export does not know is still exported, flat under its own name: nothing is lost.
  for (const auto& [name, values] : c.tensors)
    if (!taken.contains(name)) out.tensors.push_back({name, {values.size()}, values});

  out.metadata["format"] = "clradiosity-model";
  out.metadata["format_version"] = "1";
  out.metadata["producer"] = std::string("clradiosity ") + CLR_VERSION;
  out.metadata["step"] = std::to_string(c.step);
  if (averaged) out.metadata["n_module_parameters"] = "weight average (training.* holds the trained parameters)";
  out.metadata["networks"] = networks.dump();
  if (settings.is_object()) out.metadata["train_config"] = settings.dump();
  if (fs::exists(RunDirectory::scene_path(dir)))
    out.metadata["scene"] = read_json_file(RunDirectory::scene_path(dir), "run scene record").dump();
  return out;
}

}  // namespace clr::radiosity
