#include "nn/export.hpp"

#include "nn/encoder.hpp"
#include "nn/hashgrid.hpp"

namespace clr::nn {
namespace {

std::string layer_name(std::size_t l, const char* what) { return "mlp.layers." + std::to_string(l) + "." + what; }
std::string level_name(std::size_t l) { return "grid.levels." + std::to_string(l); }

void split_mlp(const std::vector<float>& flat, const NetworkConfig& config, const std::string& prefix,
               SafeTensors& out) {
  const auto layers = mlp_layer_shapes(config);
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const MlpLayerShape& layer = layers[l];
    SafeTensor w{prefix + layer_name(l, "weight"), {layer.outputs, layer.inputs}, {}};
    w.values.resize(layer.inputs * layer.outputs);
    for (std::size_t i = 0; i < layer.inputs; ++i)
      for (std::size_t o = 0; o < layer.outputs; ++o)
        w.values[o * layer.inputs + i] = flat[layer.offset + i * layer.outputs + o];
    const auto bias = flat.begin() + std::ptrdiff_t(layer.offset + layer.inputs * layer.outputs);
    out.tensors.push_back(std::move(w));
    out.tensors.push_back(
        {prefix + layer_name(l, "bias"), {layer.outputs}, {bias, bias + std::ptrdiff_t(layer.outputs)}});
  }
}

void split_grid(const std::vector<float>& table, const NetworkConfig& config, const std::string& prefix,
                SafeTensors& out) {
  const std::size_t F = config.encoder.grid->features;
  const auto levels = hashgrid_levels(*config.encoder.grid);
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const auto begin = table.begin() + std::ptrdiff_t(std::size_t(levels[l].offset) * F);
    out.tensors.push_back({prefix + level_name(l),
                           {levels[l].entries, F},
                           {begin, begin + std::ptrdiff_t(std::size_t(levels[l].entries) * F)}});
  }
}

}  // namespace

void add_network_tensors(const Checkpoint& c, const std::string& path, const NetworkConfig& config,
                         const std::string& prefix, bool optimizer_state, SafeTensors& out,
                         std::set<std::string>& taken) {
  const std::size_t mlp = mlp_parameter_count(config), grid = grid_parameter_count(config);
  // The parameters first, then each moment: a reader that wants the weights alone finds them together.
  for (const std::string state : {"", "adam.m.", "adam.v."}) {
    if (!state.empty() && !optimizer_state) continue;
    const std::string suffix = state.empty() ? "" : "." + state.substr(0, state.size() - 1);  // ".adam.m"
    const std::string mlp_name = prefix + "mlp" + (state.empty() ? ".params" : suffix);
    if (state.empty() || c.has(mlp_name)) {
      split_mlp(c.tensor(path, mlp_name, mlp), config, prefix + state, out);
      taken.insert(mlp_name);
    }
    const std::string grid_name = prefix + "grid" + (state.empty() ? ".table" : suffix);
    if (grid && (state.empty() || c.has(grid_name))) {
      split_grid(c.tensor(path, grid_name, grid), config, prefix + state, out);
      taken.insert(grid_name);
    }
  }
  // Moments the export leaves out still count as taken: they are not tensors of an unknown kind.
  for (const char* name : {"mlp.adam.m", "mlp.adam.v", "grid.adam.m", "grid.adam.v"}) taken.insert(prefix + name);
}

nlohmann::ordered_json describe_network(const NetworkConfig& config, const std::string& prefix) {
  using json = nlohmann::ordered_json;
  json encoding = json::array();
  std::size_t column = 0;
  const auto columns = [&](std::size_t n) {
    json range = {column, column + n};
    column += n;
    return range;
  };
  const auto& e = config.encoder;
  if (e.grid) {
    const auto& g = *e.grid;
    json levels = json::array();
    const auto layout = hashgrid_levels(g);
    for (std::size_t l = 0; l < layout.size(); ++l)
      levels.push_back({{"tensor", prefix + level_name(l)},
                        {"resolution", layout[l].resolution},
                        {"dense", layout[l].dense},
                        {"entries", layout[l].entries}});
    encoding.push_back(
        {{"part", "hash_grid"},
         {"input", "position"},
         {"columns", columns(g.levels * g.features)},
         {"features_per_level", g.features},
         {"bbox_lo", g.bbox_lo},
         {"bbox_hi", g.bbox_hi},
         {"levels", levels},
         {"rule",
          "float32: p = clamp((x - bbox_lo) * (1 / (bbox_hi - bbox_lo)), 0, 1); per level: q = p * resolution, "
          "c = min(floor(q), resolution - 1), t = q - c; each corner v = c + d, d in {0,1}^3, weighs "
          "prod(d ? t : 1 - t); its row of the level's tensor is v.x + (resolution + 1) * (v.y + (resolution + 1) * "
          "v.z) where dense, else (v.x ^ (v.y * 2654435761) ^ (v.z * 805459861)) mod 2^32 & (entries - 1); level l "
          "fills columns [l * features_per_level, (l + 1) * features_per_level) of the part with the weighted sum "
          "of its corners' rows"}});
  }
  for (const auto& [on, input] : {std::pair{e.sh_direction, "direction"}, std::pair{e.sh_normal, "normal"}})
    if (on)
      encoding.push_back({{"part", "spherical_harmonics"},
                          {"input", input},
                          {"columns", columns(16)},
                          {"degree", 4},
                          {"rule",
                           "real SH of bands 0-3 of the unit vector (x, y, z), as tiny-cuda-nn's SphericalHarmonics: "
                           "0.28209479177387814, -0.48860251190291987 y, 0.48860251190291987 z, "
                           "-0.48860251190291987 x, 1.0925484305920792 xy, -1.0925484305920792 yz, "
                           "0.94617469575755997 z^2 - 0.31539156525251999, -1.0925484305920792 xz, "
                           "0.54627421529603959 (x^2 - y^2), 0.59004358992664352 y (-3 x^2 + y^2), "
                           "2.8906114426405538 xyz, 0.45704579946446572 y (1 - 5 z^2), "
                           "0.3731763325901154 z (5 z^2 - 3), 0.45704579946446572 x (1 - 5 z^2), "
                           "1.4453057213202769 z (x^2 - y^2), 0.59004358992664352 x (-x^2 + 3 y^2)"}});
  for (const auto& [on, input, n] :
       {std::tuple{e.albedo, "albedo", std::size_t(3)}, std::tuple{e.roughness, "roughness", std::size_t(1)}})
    if (on) encoding.push_back({{"part", "identity"}, {"input", input}, {"columns", columns(n)}});

  json layers = json::array();
  const auto shapes = mlp_layer_shapes(config);
  for (std::size_t l = 0; l < shapes.size(); ++l) {
    const bool last = l + 1 == shapes.size();
    layers.push_back({{"weight", prefix + layer_name(l, "weight")},
                      {"bias", prefix + layer_name(l, "bias")},
                      {"inputs", shapes[l].inputs},
                      {"outputs", shapes[l].outputs},
                      {"activation", !last                                               ? "relu"
                                     : config.output_activation == OutputActivation::Abs ? "abs"
                                                                                         : "none"}});
  }
  json described = json::parse(to_json(config).dump());
  described["output_scale"] = config.output_scale;  // to_json leaves out the default
  json albedo_factor = nullptr;
  if (config.albedo_factor) albedo_factor = {{"input", "albedo"}, {"floor", kAlbedoFloor}};
  return {{"prefix", prefix},
          {"raw_input",
           {{"columns", kRawInputs},
            {"position", {raw::kPosition, raw::kPosition + 3}},
            {"direction", {raw::kDirection, raw::kDirection + 3}},
            {"normal", {raw::kNormal, raw::kNormal + 3}},
            {"albedo", {raw::kAlbedo, raw::kAlbedo + 3}},
            {"roughness", {raw::kRoughness, raw::kRoughness + 1}}}},
          {"encoding", encoding},
          {"encoded_columns", column},
          {"mlp", layers},
          {"output_scale", config.output_scale},
          {"albedo_factor", albedo_factor},
          {"output",
           "output_scale * activation(W x + b) of the last layer, times max(albedo, floor) per channel where "
           "albedo_factor is not null; hidden layers h = relu(W x + b); x = the encoding's columns in order"},
          {"config", described}};
}

}  // namespace clr::nn
