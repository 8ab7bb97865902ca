#pragma once
// A fully connected network: `hidden_layers` dense layers of `width` with ReLU, then a dense output layer
// (no activation, or abs for the N-Module's non-negative radiance). All weights and biases live in one parameter
// buffer (and one gradient buffer) so Adam is a single launch.
//
// Layout of layer l (fan_in → fan_out) inside the buffer: W_l as [fan_in × fan_out] row-major, then b_l
// [fan_out]. Storing W transposed relative to PyTorch's [out × in] makes the forward product Y = X·W a plain
// row-major product (the fast case of the own GEMM); backward needs dX = dZ·Wᵀ and dW = Xᵀ·dZ.
//
// Batches are processed in chunks of at most `max_chunk_rows` rows, so no activation buffer exceeds the
// device's max allocation (1 GiB on PoCL) whatever the batch.
#include <cstdint>
#include <optional>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "nn/gemm.hpp"

namespace clr::nn {

enum class OutputActivation { None, Abs };

// The hidden and output layers' initial weights. He: uniform with variance 2/fan_in, zero biases (ReLU
// activations keep their scale through depth). Torch: PyTorch's nn.Linear default, weights and biases uniform in
// ±1/sqrt(fan_in) (a third of He's variance), what the Neural Radiosity authors' code trains from.
enum class WeightInit { He, Torch };

struct MlpConfig {
  std::size_t inputs = 0;
  std::size_t width = 64;
  std::size_t hidden_layers = 3;
  std::size_t outputs = 32;
  OutputActivation output_activation = OutputActivation::None;
  float output_scale = 1;  // infer() only (NetworkConfig::output_scale)
  float output_init = 1;   // the output layer's initial weights' scale (NetworkConfig::output_init)
  WeightInit init = WeightInit::He;
  std::size_t max_chunk_rows = 65536;  // further capped by the device's max allocation
  // Small networks where the one-launch kernels (kernels/mlp_fused.cl) apply — width and outputs multiples of 16
  // and ≤ 64, 1-4 hidden layers, no output activation (the I-Module) — take them (the forward in one launch; the
  // backward's dZ chain, dL/dinput and bias sums in one, then a dW GEMM a layer) or the per-layer GEMMs: Probe
  // times a training forward and backward on both once per device and shape (nn/probe_cache.hpp) and keeps the
  // faster: which one wins differs between CPUs (docs/results/benchmarks.md).
  enum class SmallPath { Probe, Fused, Layers } small_path = SmallPath::Probe;
};

// What forward_train keeps for backward: the input (not owned, must stay alive and unchanged until backward),
// every hidden activation, and the output layer's pre-activation where the output activation needs it.
// Reuse one MlpContext across steps: buffers are only reallocated when a batch needs more rows.
struct MlpContext {
  std::size_t rows = 0;
  std::size_t chunk_rows = 0;
  const cl::Buffer<float>* input = nullptr;
  std::vector<cl::Buffer<float>> hidden;  // chunk c, layer l at [c · hidden_layers + l]: [chunk_rows × width]
  cl::Buffer<float> pre_output;           // [rows × outputs], only for OutputActivation::Abs
  cl::Buffer<float> output;               // [rows × outputs]
};

class Mlp {
 public:
  Mlp(cl::Context& ctx, Gemm& gemm, MlpConfig config, std::uint64_t seed);

  const MlpConfig& config() const { return config_; }
  std::size_t layer_count() const { return config_.hidden_layers + 1; }
  std::size_t fan_in(std::size_t layer) const;
  std::size_t fan_out(std::size_t layer) const;
  std::size_t weight_offset(std::size_t layer) const { return offsets_[layer]; }
  std::size_t bias_offset(std::size_t layer) const { return offsets_[layer] + fan_in(layer) * fan_out(layer); }
  std::size_t parameter_count() const { return offsets_.back(); }

  cl::Buffer<float>& params() { return params_; }
  cl::Buffer<float>& grads() { return grads_; }
  const cl::Buffer<float>& params() const { return params_; }

  // input: [rows × inputs] row-major. Fills ctx (ctx.output: [rows × outputs]).
  void forward_train(const cl::Buffer<float>& input, std::size_t rows, MlpContext& ctx);
  MlpContext forward_train(const cl::Buffer<float>& input, std::size_t rows);
  // Accumulates dL/dparams into grads() from d_output [rows × outputs]; writes dL/dinput into *d_input
  // ([rows × inputs]) when given (needed when the input encoding is trainable), only its first `d_input_cols`
  // columns when that is set (the trainable part of an encoding comes first; the rest needs no gradient).
  void backward(MlpContext& ctx, const cl::Buffer<float>& d_output, cl::Buffer<float>* d_input = nullptr,
                std::size_t d_input_cols = 0);
  // Inference without saved activations: output rows [out_row, out_row + rows) of a [· × outputs] buffer.
  void infer(const cl::Buffer<float>& input, std::size_t rows, cl::Buffer<float>& output, std::size_t out_row = 0);

  std::size_t chunk_rows(std::size_t rows) const;
  bool fused() const { return fused_.has_value(); }

 private:
  cl::Buffer<float>& workspace(std::size_t i, std::size_t count);
  void bias_grad(std::size_t rows, std::size_t cols, MatRef dy, const cl::Buffer<float>& saved, std::size_t s_off,
                 std::size_t s_ld, unsigned act, MatRef dz, std::size_t bias_off);

  cl::Context* ctx_;
  Gemm* gemm_;
  MlpConfig config_;
  std::vector<std::size_t> offsets_;  // per layer, and the total at the end
  cl::Buffer<float> params_, grads_;
  std::vector<cl::Buffer<float>> workspace_;
  void fused_forward(const cl::Buffer<float>& input, std::size_t x_row, std::size_t rows, cl::Buffer<float>& out,
                     std::size_t out_row, const std::vector<cl::Buffer<float>>* hidden, std::size_t hidden_base);
  void fused_backward(MlpContext& ctx, std::size_t r0, std::size_t ci, std::size_t rows,
                      const cl::Buffer<float>& d_output, cl::Buffer<float>* d_input, std::size_t d_input_cols);

  struct Fused {
    cl::Kernel forward, backward, bias_reduce;
  };
  cl::Kernel act_backward_, bias_reduce_, abs_, scale_;
  std::optional<Fused> fused_;
};

}  // namespace clr::nn
