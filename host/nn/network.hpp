#pragma once
// A trainable network = input encoder (hash grid, SH, raw features) + MLP, each with its Adam state.
// The trainer's view (docs/design.md §2): raw inputs [rows × kRawInputs] on the device in, [rows × outputs] out.
//   NetworkContext c;  net.forward_train(raw, rows, c);   // c.output(): predictions, activations kept
//   net.backward(c, d_output);                             // accumulates parameter gradients
//   net.adam_step();                                       // updates and clears them
//   net.infer(raw, rows, out);                             // no saved activations, chunked for any batch
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "nn/adam.hpp"
#include "nn/checkpoint.hpp"
#include "nn/encoder.hpp"
#include "nn/gemm.hpp"
#include "nn/mlp.hpp"

namespace clr::nn {

struct NetworkConfig {
  EncoderConfig encoder;
  std::size_t width = 64;
  std::size_t hidden_layers = 3;
  std::size_t outputs = 32;
  OutputActivation output_activation = OutputActivation::None;
  // infer() returns output_scale × the MLP's output; forward_train's outputs (what a loss sees) stay in units of
  // output_scale, the units in which the initial weights and Adam's step sizes fit. The N-Module's is the scene's
  // radiance scale (radiosity/radiance_scale.hpp), so a scene emitting 1e5 trains as one emitting 1.
  float output_scale = 1;
  // The output layer's initial weights, as a fraction of He's: the N-Module's start at a tenth, so that its first
  // image is dark and training brings the light in, rather than starting bright and pulling the light down — on a
  // room lit through a door gap (scenes/door-gap.xml) a full-scale start was still 1.3× too bright at 150 steps,
  // where a tenth-scale one was within 2 % (tests/radiosity/runaway_slow_test.cpp; docs/method.md).
  float output_init = 1;
  WeightInit init = WeightInit::He;  // "he" or "torch" in the JSON (nn/mlp.hpp)
  // The outputs (3, RGB) are multiplied by the surface's albedo (raw columns 9-11, at least kAlbedoFloor): the MLP
  // learns radiance over albedo, which for a diffuse surface is its irradiance / π, smooth across a texture, and the
  // texture itself comes exact from the scene — the factorisation of Müller et al.'s neural radiance cache. Without
  // it the hash grid must carry every texel of a wallpaper or a wood grain (docs/method.md, "Albedo").
  bool albedo_factor = false;
  std::size_t max_chunk_rows = 65536;
  AdamConfig adam;
  GemmChoice gemm = GemmChoice::Auto;  // the engine config's `gemm: auto|fp32|own|clblast`
  std::uint64_t seed = 1;
};

// ISNR §4.3: N-Module = hash grid + SH(ω_o) + SH(n) + albedo → 4 × 512 ReLU → 3, abs (non-negative radiance).
NetworkConfig n_module_config(const std::array<float, 3>& bbox_lo, const std::array<float, 3>& bbox_hi);

nlohmann::json to_json(const NetworkConfig& c);

// The MLP's and the hash-grid table's parameter counts for a config, without building anything (a checkpoint's
// tensors are checked against them before its config allocates device memory). Network::parameter_count's twin.
std::size_t mlp_parameter_count(const NetworkConfig& c);
// Layer l of a config's MLP (fan_in → fan_out) and where its W starts in the flat parameters, b following W
// (nn/mlp.hpp's layout): the checkpoint's count above and the export's tensors read it.
struct MlpLayerShape {
  std::size_t inputs, outputs, offset;
};
std::vector<MlpLayerShape> mlp_layer_shapes(const NetworkConfig& c);
// The encoder's output columns (the MLP's inputs) for a config, as Encoder lays them out: grid features, SH of ω_o
// and of n (16 each), albedo (3), roughness (1).
std::size_t encoded_columns(const EncoderConfig& e);
std::size_t grid_parameter_count(const NetworkConfig& c);
NetworkConfig network_config_from_json(const nlohmann::json& j);  // throws InputError naming a bad entry
// `base` with a JSON merge patch (RFC 7396) applied: a user's overrides of a module's defaults. Unlike RFC 7396, a
// null is a value, not a removal: `encoder.grid: null` is "no hash grid" (docs/cli.md), and a null elsewhere is an
// InputError.
NetworkConfig merge_patch(const NetworkConfig& base, const nlohmann::json& patch);

// The albedo factor's floor: a black albedo with a specular layer (a black plastic) still reflects, and a factor of
// 0 would leave the network nothing to say there.
inline constexpr float kAlbedoFloor = 0.02f;

struct NetworkContext {
  std::size_t rows = 0;
  const cl::Buffer<float>* raw = nullptr;  // not owned; must stay unchanged until backward
  cl::Buffer<float> encoded;               // [rows × encoder outputs]
  cl::Buffer<float> d_encoded;
  cl::Buffer<float> d_factored;  // dL/d(MLP output) with the albedo factor
  MlpContext mlp;
  const cl::Buffer<float>& output() const { return mlp.output; }
};

class Network {
 public:
  Network(cl::Context& ctx, NetworkConfig config);

  const NetworkConfig& config() const { return config_; }
  std::size_t outputs() const { return config_.outputs; }
  Encoder& encoder() { return encoder_; }
  const Encoder& encoder() const { return encoder_; }
  Mlp& mlp() { return mlp_; }
  const Mlp& mlp() const { return mlp_; }
  Gemm& gemm() { return gemm_; }
  std::size_t parameter_count() const;

  void forward_train(const cl::Buffer<float>& raw, std::size_t rows, NetworkContext& c);
  void backward(NetworkContext& c, const cl::Buffer<float>& d_output);
  void infer(const cl::Buffer<float>& raw, std::size_t rows, cl::Buffer<float>& output);
  void adam_step();
  // Scales every Adam's learning rate (MLP and encoder) from the next step on.
  void set_learning_rate_scale(float s);
  std::uint64_t steps() const { return adam_.steps(); }

  // Checkpoint (nn/checkpoint.hpp): config, parameters, optimiser state, step and the trainer's RNG state.
  void save(const std::string& path, const std::string& rng_state = "") const;
  Checkpoint checkpoint(const std::string& rng_state = "") const;
  // Parameters and optimiser state as tensors named `prefix` + "mlp.params" etc., so that a second network (the
  // I-Module) can travel in the same checkpoint file as the first.
  void add_tensors(Checkpoint& c, const std::string& prefix) const;
  // Restores parameters and optimiser state; returns the saved RNG state. A file written for a different
  // config, or damaged, throws InputError naming the file and the problem.
  std::string load(const std::string& path);
  // The tensors add_tensors wrote under `prefix` (sizes checked; InputError naming `path` otherwise) and the step.
  void restore(const Checkpoint& c, const std::string& path, const std::string& prefix);
  // The parameters alone (no optimiser state or step), for a copy that is only evaluated: the I-Module as it was
  // before its last update (radiosity::Trainer's lagged guide).
  void add_parameter_tensors(Checkpoint& c, const std::string& prefix) const;
  void restore_parameters(const Checkpoint& c, const std::string& path, const std::string& prefix);
  // Takes `other`'s parameters (a network of the same config) on the device, enqueued.
  void copy_parameters(const Network& other);

  // An exponential moving average of the parameters (MLP and hash table; Polyak averaging, as Müller et al.'s
  // neural radiance cache renders with): start_average() begins it at the current parameters,
  // update_average(d) folds the current ones in with weight 1 − d (after an Adam step), swap_average() exchanges
  // the parameters with the average (twice: back), so that the same inference code renders either.
  bool averaging() const { return average_mlp_.size() != 0; }
  void start_average();
  void update_average(float decay);
  void swap_average();
  // The average becomes the parameters for good (a model loaded to be rendered, not trained on).
  void adopt_average();

 private:
  cl::Context* ctx_;
  NetworkConfig config_;
  Gemm gemm_;
  Encoder encoder_;
  Mlp mlp_;
  Adam adam_;
  cl::Kernel factor_;
  cl::Kernel average_;
  cl::Buffer<float> infer_encoded_;
  cl::Buffer<float> average_mlp_, average_grid_;  // empty until start_average

  // x[off …] = y[off …] · albedo of raw rows [row0, row0 + rows) (albedo_factor).
  void apply_albedo(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows, const cl::Buffer<float>& y,
                    cl::Buffer<float>& x, std::size_t off);
};

// The network's weight average in place of its parameters for a scope (nothing when it keeps none): what is
// evaluated or previewed during training is the model a run renders.
class AverageSwapped {
 public:
  explicit AverageSwapped(Network& net) : net_(net.averaging() ? &net : nullptr) {
    if (net_) net_->swap_average();
  }
  ~AverageSwapped() {
    if (net_) net_->swap_average();
  }
  AverageSwapped(const AverageSwapped&) = delete;
  AverageSwapped& operator=(const AverageSwapped&) = delete;

 private:
  Network* net_;
};

}  // namespace clr::nn
