#include "nn/network.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "common/error.hpp"
#include "nn/checkpoint.hpp"

namespace clr::nn {
namespace {

MlpConfig mlp_config(const NetworkConfig& c, std::size_t inputs) {
  MlpConfig m;
  m.inputs = inputs;
  m.width = c.width;
  m.hidden_layers = c.hidden_layers;
  m.outputs = c.outputs;
  m.output_activation = c.output_activation;
  m.max_chunk_rows = c.max_chunk_rows;
  return m;
}

// Encoder parameters are seeded apart from the MLP's so that changing one part does not reshuffle the other.
constexpr std::uint64_t kEncoderSeedSalt = 0x9e3779b97f4a7c15ull;

// The shortest decimal that reads back as `f`, so config.json says 0.9, not 0.8999999761581421.
double shortest(float f) {
  char text[32];
  for (int digits = 1; digits < 9; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, double(f));
    // Read back as the JSON loader does: a double, then narrowed.
    if (const double d = std::strtod(text, nullptr); float(d) == f) return d;
  }
  return double(f);
}

nlohmann::json shortest(const std::array<float, 3>& v) { return {shortest(v[0]), shortest(v[1]), shortest(v[2])}; }

nlohmann::json adam_json(const AdamConfig& a) {
  return {{"learning_rate", shortest(a.learning_rate)},
          {"beta1", shortest(a.beta1)},
          {"beta2", shortest(a.beta2)},
          {"epsilon", shortest(a.epsilon)},
          {"weight_decay", shortest(a.weight_decay)},
          {"decay", shortest(a.decay)},
          {"decay_start", a.decay_start},
          {"decay_interval", a.decay_interval}};
}

}  // namespace

NetworkConfig n_module_config(const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  NetworkConfig c;
  c.encoder.grid->bbox_lo = lo;
  c.encoder.grid->bbox_hi = hi;
  c.encoder.albedo = true;
  c.encoder.roughness = false;
  c.width = 512;
  c.hidden_layers = 4;
  c.outputs = 3;
  c.output_activation = OutputActivation::Abs;
  return c;
}

NetworkConfig i_module_config(const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  NetworkConfig c;
  c.encoder.grid->bbox_lo = lo;
  c.encoder.grid->bbox_hi = hi;
  c.encoder.albedo = false;
  c.encoder.roughness = true;
  // A coarser, smaller grid than the N-Module's (12 levels, 2^18): the incident light's directional
  // distribution varies more slowly over the surfaces than radiance does, and the I-Module must stay a small
  // share of a step. 8 levels reach 16 · 1.5^7 ≈ 273 cells across the scene.
  c.encoder.grid->levels = 8;
  c.encoder.grid->log2_table = 16;
  c.width = 64;
  c.hidden_layers = 3;
  c.outputs = 32;
  c.output_activation = OutputActivation::None;
  return c;
}

nlohmann::json to_json(const NetworkConfig& c) {
  nlohmann::json enc = {{"sh_direction", c.encoder.sh_direction},
                        {"sh_normal", c.encoder.sh_normal},
                        {"albedo", c.encoder.albedo},
                        {"roughness", c.encoder.roughness}};
  if (c.encoder.grid) {
    const auto& g = *c.encoder.grid;
    enc["grid"] = {{"levels", g.levels},
                   {"features", g.features},
                   {"log2_table", g.log2_table},
                   {"base_resolution", g.base_resolution},
                   {"growth", g.growth},
                   {"bbox_lo", shortest(g.bbox_lo)},
                   {"bbox_hi", shortest(g.bbox_hi)}};
  } else {
    enc["grid"] = nullptr;
  }
  return {{"encoder", enc},
          {"width", c.width},
          {"hidden_layers", c.hidden_layers},
          {"outputs", c.outputs},
          {"output_activation", c.output_activation == OutputActivation::Abs ? "abs" : "none"},
          {"max_chunk_rows", c.max_chunk_rows},
          {"adam", adam_json(c.adam)},
          {"gemm", c.gemm == GemmChoice::Own       ? "own"
                   : c.gemm == GemmChoice::CLBlast ? "clblast"
                                                   : "auto"},
          {"seed", c.seed}};
}

NetworkConfig network_config_from_json(const nlohmann::json& j) {
  NetworkConfig c;
  std::string at;
  try {
    auto get = [&](const nlohmann::json& o, const char* key, auto& v) {
      at = key;
      if (o.contains(key)) v = o.at(key).get<std::decay_t<decltype(v)>>();
    };
    if (j.contains("encoder")) {
      const auto& e = j.at("encoder");
      get(e, "sh_direction", c.encoder.sh_direction);
      get(e, "sh_normal", c.encoder.sh_normal);
      get(e, "albedo", c.encoder.albedo);
      get(e, "roughness", c.encoder.roughness);
      if (e.contains("grid") && e.at("grid").is_null()) c.encoder.grid.reset();
      if (e.contains("grid") && e.at("grid").is_object()) {
        const auto& g = e.at("grid");
        auto& gc = *c.encoder.grid;
        get(g, "levels", gc.levels);
        get(g, "features", gc.features);
        get(g, "log2_table", gc.log2_table);
        get(g, "base_resolution", gc.base_resolution);
        get(g, "growth", gc.growth);
        get(g, "bbox_lo", gc.bbox_lo);
        get(g, "bbox_hi", gc.bbox_hi);
      }
    }
    get(j, "width", c.width);
    get(j, "hidden_layers", c.hidden_layers);
    get(j, "outputs", c.outputs);
    std::string act = "none", gemm = "auto";
    get(j, "output_activation", act);
    if (act != "none" && act != "abs") throw InputError("output_activation '" + act + "' is not none or abs");
    c.output_activation = act == "abs" ? OutputActivation::Abs : OutputActivation::None;
    get(j, "max_chunk_rows", c.max_chunk_rows);
    get(j, "gemm", gemm);
    c.gemm = parse_gemm_choice(gemm);
    get(j, "seed", c.seed);
    if (j.contains("adam")) {
      const auto& a = j.at("adam");
      get(a, "learning_rate", c.adam.learning_rate);
      get(a, "beta1", c.adam.beta1);
      get(a, "beta2", c.adam.beta2);
      get(a, "epsilon", c.adam.epsilon);
      get(a, "weight_decay", c.adam.weight_decay);
      get(a, "decay", c.adam.decay);
      get(a, "decay_start", c.adam.decay_start);
      get(a, "decay_interval", c.adam.decay_interval);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError("network config entry '" + at + "': " + e.what());
  }
  return c;
}

Network::Network(cl::Context& ctx, NetworkConfig config)
    : ctx_(&ctx),
      config_(config),
      gemm_(ctx, config.gemm),
      encoder_(ctx, config.encoder, config.adam, config.seed ^ kEncoderSeedSalt),
      mlp_(ctx, gemm_, mlp_config(config, encoder_.outputs()), config.seed),
      adam_(ctx, mlp_.parameter_count(), config.adam) {}

std::size_t Network::parameter_count() const {
  return mlp_.parameter_count() + (encoder_.grid() ? encoder_.grid()->params().size() : 0);
}

void Network::forward_train(const cl::Buffer<float>& raw, std::size_t rows, NetworkContext& c) {
  const std::size_t D = encoder_.outputs();
  if (c.encoded.size() < rows * D) {
    c.encoded = cl::Buffer<float>();
    c.encoded = cl::Buffer<float>(*ctx_, rows * D);
  }
  c.rows = rows;
  c.raw = &raw;
  encoder_.forward(raw, 0, rows, c.encoded);
  mlp_.forward_train(c.encoded, rows, c.mlp);
}

void Network::backward(NetworkContext& c, const cl::Buffer<float>& d_output) {
  if (!c.raw) throw std::logic_error("network: backward without forward_train");
  HashGrid* grid = encoder_.grid();
  if (grid && c.d_encoded.size() < c.rows * encoder_.outputs()) {
    c.d_encoded = cl::Buffer<float>();
    c.d_encoded = cl::Buffer<float>(*ctx_, c.rows * encoder_.outputs());
  }
  // Only the hash-grid columns (first in the encoding) carry trainable parameters below them.
  mlp_.backward(c.mlp, d_output, grid ? &c.d_encoded : nullptr, grid ? grid->outputs() : 0);
  if (grid) encoder_.backward(*c.raw, 0, c.rows, c.d_encoded);
}

void Network::infer(const cl::Buffer<float>& raw, std::size_t rows, cl::Buffer<float>& output) {
  const std::size_t D = encoder_.outputs();
  const std::size_t chunk = std::min(mlp_.chunk_rows(rows), ctx_->device().max_alloc_bytes / (sizeof(float) * D));
  if (infer_encoded_.size() < chunk * D) {
    infer_encoded_ = cl::Buffer<float>();
    infer_encoded_ = cl::Buffer<float>(*ctx_, chunk * D);
  }
  for (std::size_t r0 = 0; r0 < rows; r0 += chunk) {
    const std::size_t cr = std::min(chunk, rows - r0);
    encoder_.forward(raw, r0, cr, infer_encoded_);
    mlp_.infer(infer_encoded_, cr, output, r0);
  }
}

void Network::set_learning_rate_scale(float s) {
  adam_.set_learning_rate_scale(s);
  encoder_.set_learning_rate_scale(s);
}

void Network::adam_step() {
  adam_.step(mlp_.params(), mlp_.grads());
  encoder_.adam_step();
}

void Network::add_tensors(Checkpoint& c, const std::string& prefix) const {
  c.tensors.emplace_back(prefix + "mlp.params", mlp_.params().read());
  c.tensors.emplace_back(prefix + "mlp.adam.m", adam_.first_moment().read());
  c.tensors.emplace_back(prefix + "mlp.adam.v", adam_.second_moment().read());
  if (const HashGrid* g = encoder_.grid()) {
    c.tensors.emplace_back(prefix + "grid.table", g->params().read());
    c.tensors.emplace_back(prefix + "grid.adam.m", g->adam().first_moment().read());
    c.tensors.emplace_back(prefix + "grid.adam.v", g->adam().second_moment().read());
  }
}

void Network::save(const std::string& path, const std::string& rng_state) const {
  write_checkpoint(path, checkpoint(rng_state));
}

Checkpoint Network::checkpoint(const std::string& rng_state) const {
  Checkpoint c;
  c.config_json = to_json(config_).dump();
  c.step = adam_.steps();
  c.rng_state = rng_state;
  add_tensors(c, "");
  return c;
}

std::string Network::load(const std::string& path) {
  const Checkpoint c = read_checkpoint(path);
  nlohmann::json saved;
  try {
    saved = nlohmann::json::parse(c.config_json);
  } catch (const nlohmann::json::exception&) {
    throw InputError("checkpoint " + path + ": the stored config is not valid JSON");
  }
  // The GEMM backend and chunking change how, not what, the network computes, and the seed only the initial
  // parameters that loading overwrites: they may differ.
  auto mine = to_json(config_);
  for (auto* j : {&saved, &mine})
    for (const char* key : {"gemm", "max_chunk_rows", "seed"}) j->erase(key);
  if (saved != mine) {
    const auto diff = nlohmann::json::diff(mine, saved);
    const std::string where = diff.empty() ? "?" : diff.front().value("path", "?");
    throw InputError("checkpoint " + path + ": written for a different network config (first difference at " + where +
                     ")");
  }
  restore(c, path, "");
  return c.rng_state;
}

void Network::restore(const Checkpoint& c, const std::string& path, const std::string& prefix) {
  mlp_.params().write(c.tensor(path, prefix + "mlp.params", mlp_.params().size()));
  adam_.first_moment().write(c.tensor(path, prefix + "mlp.adam.m", adam_.first_moment().size()));
  adam_.second_moment().write(c.tensor(path, prefix + "mlp.adam.v", adam_.second_moment().size()));
  mlp_.grads().fill(0.0f);
  adam_.set_steps(c.step);
  if (HashGrid* g = encoder_.grid()) {
    g->params().write(c.tensor(path, prefix + "grid.table", g->params().size()));
    g->adam().first_moment().write(c.tensor(path, prefix + "grid.adam.m", g->params().size()));
    g->adam().second_moment().write(c.tensor(path, prefix + "grid.adam.v", g->params().size()));
    g->clear_gradient();
    g->touched().fill(std::uint8_t(0));
    g->adam().set_steps(c.step);
  }
}

}  // namespace clr::nn
