#include "nn/network.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "nn/checkpoint.hpp"
#include "nn/programs.hpp"

namespace clr::nn {
namespace {

MlpConfig mlp_config(const NetworkConfig& c, std::size_t inputs) {
  MlpConfig m;
  m.inputs = inputs;
  m.width = c.width;
  m.hidden_layers = c.hidden_layers;
  m.outputs = c.outputs;
  m.output_activation = c.output_activation;
  m.output_scale = c.output_scale;
  m.output_init = c.output_init;
  m.init = c.init;
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
  // The Neural Radiosity authors' resolutions, 2 doubling to 4096 across the scene's box: coarse cells that many
  // samples reach each step tell the rooms of a scene apart sooner (docs/method.md, "The start and the swings").
  c.encoder.grid->base_resolution = 2;
  c.encoder.grid->growth = 2.0;
  c.encoder.albedo = true;
  c.encoder.roughness = false;
  c.width = 512;
  c.hidden_layers = 4;
  c.outputs = 3;
  c.output_activation = OutputActivation::Abs;
  c.output_init = 0.1f;
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
  nlohmann::json j = {{"encoder", enc},
                      {"width", c.width},
                      {"hidden_layers", c.hidden_layers},
                      {"outputs", c.outputs},
                      {"output_activation", c.output_activation == OutputActivation::Abs ? "abs" : "none"},
                      {"max_chunk_rows", c.max_chunk_rows},
                      {"adam", adam_json(c.adam)},
                      {"gemm", c.gemm == GemmChoice::Own       ? "own"
                               : c.gemm == GemmChoice::Fp32    ? "fp32"
                               : c.gemm == GemmChoice::CLBlast ? "clblast"
                                                               : "auto"},
                      {"seed", c.seed}};
  // Written only where they are not 1, so that runs (and checkpoints) from before they existed compare equal.
  if (c.output_scale != 1.0f) j["output_scale"] = shortest(c.output_scale);
  if (c.output_init != 1.0f) j["output_init"] = shortest(c.output_init);
  if (c.init != WeightInit::He) j["init"] = "torch";
  if (c.albedo_factor) j["albedo_factor"] = true;
  if (c.encoder.grid && c.encoder.grid->dense_adam) j["encoder"]["grid"]["dense_adam"] = true;
  if (c.encoder.grid && c.encoder.grid->learning_rate_factor != 1.0f)
    j["encoder"]["grid"]["learning_rate_factor"] = shortest(c.encoder.grid->learning_rate_factor);
  return j;
}

namespace {

// Throws InputError "network config entry '<name>' must be <rule>, got <value>" unless `ok`.
template <typename T>
void require(bool ok, const std::string& name, const T& value, const char* rule) {
  if (ok) return;
  std::ostringstream got;  // not JSON, which prints NaN and infinities as null
  got << std::setprecision(9) << value;
  throw InputError("network config entry '" + name + "' must be " + rule + ", got " + got.str());
}

// Values as the network uses them (after narrowing to float: 1e300 in the JSON is inf here). The bounds are the
// ones past which a setting cannot be meant: they stop NaN, a zero width or an absurd allocation from reaching the
// device, where it would fail late (exit 1) or silently train nothing.
void validate(const NetworkConfig& c) {
  if (c.encoder.grid) {
    const auto& g = *c.encoder.grid;
    // levels, features, log2_table and base_resolution are checked where the grid is laid out (hashgrid_levels).
    require(std::isfinite(g.growth) && g.growth >= 1.0, "encoder.grid.growth", g.growth, "finite and >= 1");
    for (int i = 0; i < 3; ++i) {
      require(std::isfinite(g.bbox_lo[i]), "encoder.grid.bbox_lo", g.bbox_lo[i], "finite");
      require(std::isfinite(g.bbox_hi[i]), "encoder.grid.bbox_hi", g.bbox_hi[i], "finite");
      require(g.bbox_lo[i] < g.bbox_hi[i], "encoder.grid.bbox_hi", g.bbox_hi[i], "greater than bbox_lo on each axis");
    }
  }
  // 4096² weights per layer (64 MiB with the Adam moments' twice that) is far past the paper's 512.
  require(c.width >= 1 && c.width <= 4096, "width", c.width, "in [1, 4096]");
  require(c.hidden_layers >= 1 && c.hidden_layers <= 64, "hidden_layers", c.hidden_layers, "in [1, 64]");
  require(c.outputs >= 1 && c.outputs <= 4096, "outputs", c.outputs, "in [1, 4096]");
  require(c.max_chunk_rows >= 1, "max_chunk_rows", c.max_chunk_rows, ">= 1");
  // Beyond these the scaled outputs, or their reciprocal in the loss, leave float's normal range.
  require(c.output_scale >= 1e-30f && c.output_scale <= 1e30f, "output_scale", c.output_scale, "in [1e-30, 1e30]");
  require(c.output_init > 0.0f && c.output_init <= 1.0f, "output_init", c.output_init, "in (0, 1]");
  const auto& a = c.adam;
  // Adam moves each parameter by about the learning rate per step: above 1 nothing converges.
  require(std::isfinite(a.learning_rate) && a.learning_rate > 0 && a.learning_rate <= 1, "adam.learning_rate",
          a.learning_rate, "in (0, 1]");
  if (c.encoder.grid)  // the table's rate, like the network's, at most 1
    require(
        c.encoder.grid->learning_rate_factor > 0 && double(c.encoder.grid->learning_rate_factor) * a.learning_rate <= 1,
        "encoder.grid.learning_rate_factor", c.encoder.grid->learning_rate_factor,
        "> 0, with adam.learning_rate times it <= 1");
  // β = 1 would never forget the first gradient and divides by zero in the bias correction 1/(1 − β^t).
  require(a.beta1 >= 0 && a.beta1 < 1, "adam.beta1", a.beta1, "in [0, 1)");
  require(a.beta2 >= 0 && a.beta2 < 1, "adam.beta2", a.beta2, "in [0, 1)");
  require(std::isfinite(a.epsilon) && a.epsilon > 0, "adam.epsilon", a.epsilon, "finite and > 0");
  require(std::isfinite(a.weight_decay) && a.weight_decay >= 0, "adam.weight_decay", a.weight_decay, "finite and >= 0");
  require(a.decay > 0 && a.decay <= 1, "adam.decay", a.decay, "in (0, 1]");
  require(a.decay_interval >= 1, "adam.decay_interval", a.decay_interval, ">= 1");
}

// RFC 7386's merge, but a null is kept as a value rather than read as "remove the key": the documented
// `encoder.grid: null` means "no hash grid", and removing the key instead brought back a default grid over the
// unit cube, not the scene's box. A null anywhere else is refused (there, removing a key restores a default that the
// patch's author did not ask for, such as a scene-derived box; no other value may be null).
void merge_keeping_nulls(nlohmann::json& target, const nlohmann::json& patch, const std::string& at) {
  if (!patch.is_object()) {
    target = patch;
    return;
  }
  if (!target.is_object()) target = nlohmann::json::object();
  for (const auto& [key, value] : patch.items()) {
    const std::string name = at + clip(key);
    if (value.is_null() && name != "encoder.grid")
      throw InputError("network config entry '" + name + "' is null: only encoder.grid may be (no hash grid)");
    if (value.is_object())
      merge_keeping_nulls(target[key], value, name + ".");
    else
      target[key] = value;
  }
}

}  // namespace

NetworkConfig merge_patch(const NetworkConfig& base, const nlohmann::json& patch) {
  nlohmann::json j = to_json(base);
  merge_keeping_nulls(j, patch, "");
  return network_config_from_json(j);
}

NetworkConfig network_config_from_json(const nlohmann::json& j) {
  // Anything but an object would read as "every key absent", i.e. the defaults, whatever the file held.
  if (!j.is_object()) throw InputError("network config must be a JSON object, not " + clip(j.dump()));
  NetworkConfig c;
  std::string at;
  try {
    // `prefix` names the enclosing objects, so a message says "adam.beta2", not just "beta2".
    auto get = [&](const nlohmann::json& o, const std::string& prefix, const char* key, auto& v) {
      using T = std::decay_t<decltype(v)>;
      at = prefix + key;
      if (!o.contains(key)) return;
      const auto& x = o.at(key);
      // nlohmann converts 2.5 to 2 and -1 to 2^64 - 1 for an unsigned target: both are mistakes in a config.
      if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
        const bool negative = x.is_number_integer() && !x.is_number_unsigned() && x.template get<long long>() < 0;
        if (!x.is_number_integer() || (std::is_unsigned_v<T> && negative))
          throw InputError("network config entry '" + at + "' must be a non-negative integer, got " + clip(x.dump()));
      }
      v = x.template get<T>();
    };
    if (j.contains("encoder")) {
      const auto& e = j.at("encoder");
      get(e, "encoder.", "sh_direction", c.encoder.sh_direction);
      get(e, "encoder.", "sh_normal", c.encoder.sh_normal);
      get(e, "encoder.", "albedo", c.encoder.albedo);
      get(e, "encoder.", "roughness", c.encoder.roughness);
      if (e.contains("grid") && e.at("grid").is_null()) c.encoder.grid.reset();
      if (e.contains("grid") && e.at("grid").is_object()) {
        const auto& g = e.at("grid");
        auto& gc = *c.encoder.grid;
        get(g, "encoder.grid.", "levels", gc.levels);
        get(g, "encoder.grid.", "features", gc.features);
        get(g, "encoder.grid.", "log2_table", gc.log2_table);
        get(g, "encoder.grid.", "base_resolution", gc.base_resolution);
        get(g, "encoder.grid.", "growth", gc.growth);
        get(g, "encoder.grid.", "bbox_lo", gc.bbox_lo);
        get(g, "encoder.grid.", "bbox_hi", gc.bbox_hi);
        get(g, "encoder.grid.", "dense_adam", gc.dense_adam);
        get(g, "encoder.grid.", "learning_rate_factor", gc.learning_rate_factor);
      }
    }
    get(j, "", "width", c.width);
    get(j, "", "hidden_layers", c.hidden_layers);
    get(j, "", "outputs", c.outputs);
    std::string act = "none", gemm = "auto";
    get(j, "", "output_activation", act);
    if (act != "none" && act != "abs") throw InputError("output_activation '" + act + "' is not none or abs");
    c.output_activation = act == "abs" ? OutputActivation::Abs : OutputActivation::None;
    get(j, "", "max_chunk_rows", c.max_chunk_rows);
    get(j, "", "output_scale", c.output_scale);
    get(j, "", "output_init", c.output_init);
    get(j, "", "albedo_factor", c.albedo_factor);
    std::string init = "he";
    get(j, "", "init", init);
    if (init != "he" && init != "torch")
      throw InputError("network config entry 'init' must be he or torch, got '" + clip(init) + "'");
    c.init = init == "torch" ? WeightInit::Torch : WeightInit::He;
    get(j, "", "gemm", gemm);
    c.gemm = parse_gemm_choice(gemm);
    get(j, "", "seed", c.seed);
    if (j.contains("adam")) {
      const auto& a = j.at("adam");
      get(a, "adam.", "learning_rate", c.adam.learning_rate);
      get(a, "adam.", "beta1", c.adam.beta1);
      get(a, "adam.", "beta2", c.adam.beta2);
      get(a, "adam.", "epsilon", c.adam.epsilon);
      get(a, "adam.", "weight_decay", c.adam.weight_decay);
      get(a, "adam.", "decay", c.adam.decay);
      get(a, "adam.", "decay_start", c.adam.decay_start);
      get(a, "adam.", "decay_interval", c.adam.decay_interval);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError("network config entry '" + at + "': " + clip(e.what(), 200));
  }
  nlohmann::json kept = to_json(c);
  kept["output_scale"] = c.output_scale;  // to_json leaves out the defaults
  kept["output_init"] = c.output_init;
  kept["init"] = c.init == WeightInit::Torch ? "torch" : "he";
  kept["albedo_factor"] = c.albedo_factor;
  if (c.encoder.grid) {
    kept["encoder"]["grid"]["dense_adam"] = c.encoder.grid->dense_adam;
    kept["encoder"]["grid"]["learning_rate_factor"] = c.encoder.grid->learning_rate_factor;
  }
  require_known_and_kept(j, kept, "network config");
  validate(c);
  return c;
}

std::size_t grid_parameter_count(const NetworkConfig& c) {
  if (!c.encoder.grid) return 0;
  std::size_t entries = 0;
  for (const auto& level : hashgrid_levels(*c.encoder.grid)) entries += level.entries;
  return entries * c.encoder.grid->features;
}

std::size_t encoded_columns(const EncoderConfig& e) {
  return (e.grid ? e.grid->levels * e.grid->features : 0) + (e.sh_direction ? 16 : 0) + (e.sh_normal ? 16 : 0) +
         (e.albedo ? 3 : 0) + (e.roughness ? 1 : 0);
}

std::vector<MlpLayerShape> mlp_layer_shapes(const NetworkConfig& c) {
  std::vector<MlpLayerShape> layers;
  std::size_t offset = 0;
  for (std::size_t l = 0; l <= c.hidden_layers; ++l) {
    const std::size_t in = l == 0 ? encoded_columns(c.encoder) : c.width;
    const std::size_t out = l == c.hidden_layers ? c.outputs : c.width;
    layers.push_back({in, out, offset});
    offset += in * out + out;
  }
  return layers;
}

std::size_t mlp_parameter_count(const NetworkConfig& c) {
  const MlpLayerShape last = mlp_layer_shapes(c).back();
  return last.offset + last.inputs * last.outputs + last.outputs;
}

Network::Network(cl::Context& ctx, NetworkConfig config)
    : ctx_(&ctx),
      config_(config),
      gemm_(ctx, config.gemm),
      encoder_(ctx, config.encoder, config.adam, config.seed ^ kEncoderSeedSalt),
      mlp_(ctx, gemm_, mlp_config(config, encoder_.outputs()), config.seed),
      adam_(ctx, mlp_.parameter_count(), config.adam),
      factor_(ctx.program(programs::mlp).kernel("albedo_factor")),
      average_(ctx.program(programs::adam).kernel("average_f32")) {
  // Checked here rather than with the other entries: a patch is validated over the generic defaults (32 outputs)
  // before it meets the N-Module's 3.
  if (config_.albedo_factor && config_.outputs != 3)
    throw InputError("network config entry 'albedo_factor' needs 3 outputs (RGB radiance), got " +
                     std::to_string(config_.outputs));
}

void Network::apply_albedo(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows, const cl::Buffer<float>& y,
                           cl::Buffer<float>& x, std::size_t off) {
  const auto u32 = [](std::size_t v) { return static_cast<cl_uint>(v); };
  const std::size_t C = config_.outputs;
  factor_.args(u32(rows), u32(C), raw, u32(row0), u32(kRawInputs), u32(raw::kAlbedo), kAlbedoFloor, y, x, u32(off))
      .launch(rows * C);
}

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
  // In place: the MLP's backward reads its pre-activation, not its output.
  if (config_.albedo_factor) apply_albedo(raw, 0, rows, c.mlp.output, c.mlp.output, 0);
}

void Network::backward(NetworkContext& c, const cl::Buffer<float>& d_output) {
  if (!c.raw) throw std::logic_error("network: backward without forward_train");
  HashGrid* grid = encoder_.grid();
  if (grid && c.d_encoded.size() < c.rows * encoder_.outputs()) {
    c.d_encoded = cl::Buffer<float>();
    c.d_encoded = cl::Buffer<float>(*ctx_, c.rows * encoder_.outputs());
  }
  const cl::Buffer<float>* d_mlp = &d_output;
  if (config_.albedo_factor) {
    if (c.d_factored.size() < c.rows * config_.outputs) {
      c.d_factored = cl::Buffer<float>();
      c.d_factored = cl::Buffer<float>(*ctx_, c.rows * config_.outputs);
    }
    apply_albedo(*c.raw, 0, c.rows, d_output, c.d_factored, 0);
    d_mlp = &c.d_factored;
  }
  // Only the hash-grid columns (first in the encoding) carry trainable parameters below them.
  mlp_.backward(c.mlp, *d_mlp, grid ? &c.d_encoded : nullptr, grid ? grid->outputs() : 0);
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
    if (config_.albedo_factor) apply_albedo(raw, r0, cr, output, output, r0 * config_.outputs);
  }
}

void Network::start_average() {
  average_mlp_ = cl::Buffer<float>(*ctx_, mlp_.params().size());
  average_mlp_.copy_from(mlp_.params());
  if (HashGrid* g = encoder_.grid()) {
    average_grid_ = cl::Buffer<float>(*ctx_, g->params().size());
    average_grid_.copy_from(g->params());
  }
}

void Network::update_average(float decay) {
  if (!averaging()) throw std::logic_error("network: update_average before start_average");
  const auto fold = [&](const cl::Buffer<float>& p, cl::Buffer<float>& a) {
    average_.args(static_cast<cl_uint>(p.size()), decay, p, a).launch(p.size());
  };
  fold(mlp_.params(), average_mlp_);
  if (HashGrid* g = encoder_.grid()) fold(g->params(), average_grid_);
}

void Network::swap_average() {
  if (!averaging()) throw std::logic_error("network: swap_average before start_average");
  std::swap(mlp_.params(), average_mlp_);
  if (HashGrid* g = encoder_.grid()) std::swap(g->params(), average_grid_);
}

void Network::adopt_average() {
  if (!averaging()) return;
  swap_average();
  average_mlp_ = cl::Buffer<float>();
  average_grid_ = cl::Buffer<float>();
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
  if (averaging()) {
    c.tensors.emplace_back(prefix + "mlp.average", average_mlp_.read());
    if (encoder_.grid()) c.tensors.emplace_back(prefix + "grid.average", average_grid_.read());
  }
}

void Network::add_parameter_tensors(Checkpoint& c, const std::string& prefix) const {
  c.tensors.emplace_back(prefix + "mlp.params", mlp_.params().read());
  if (const HashGrid* g = encoder_.grid()) c.tensors.emplace_back(prefix + "grid.table", g->params().read());
}

void Network::restore_parameters(const Checkpoint& c, const std::string& path, const std::string& prefix) {
  mlp_.params().write(c.tensor(path, prefix + "mlp.params", mlp_.params().size()));
  if (HashGrid* g = encoder_.grid()) g->params().write(c.tensor(path, prefix + "grid.table", g->params().size()));
}

void Network::copy_parameters(const Network& other) {
  mlp_.params().copy_from(other.mlp_.params());
  if (HashGrid* g = encoder_.grid()) g->params().copy_from(other.encoder_.grid()->params());
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
  nlohmann::json saved = parse_json(c.config_json, "the network config of checkpoint " + path);
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
  if (c.has(prefix + "mlp.average")) {
    start_average();
    average_mlp_.write(c.tensor(path, prefix + "mlp.average", average_mlp_.size()));
    if (HashGrid* g = encoder_.grid()) average_grid_.write(c.tensor(path, prefix + "grid.average", g->params().size()));
  }
}

}  // namespace clr::nn
