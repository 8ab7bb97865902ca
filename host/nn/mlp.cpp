#include "nn/mlp.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "nn/probe_cache.hpp"
#include "nn/programs.hpp"

namespace clr::nn {
namespace {
constexpr unsigned kBwdNone = 0, kBwdRelu = 1, kBwdAbs = 2;  // BWD_* in kernels/mlp.cl
constexpr std::size_t kFusedRows = 4, kFusedGroup = 16;      // RPI and GROUP in kernels/mlp_fused.cl
}  // namespace

Mlp::Mlp(cl::Context& ctx, Gemm& gemm, MlpConfig config, std::uint64_t seed)
    : ctx_(&ctx),
      gemm_(&gemm),
      config_(config),
      act_backward_(ctx.program(programs::mlp).kernel("act_backward_bias_grad")),
      bias_reduce_(ctx.program(programs::mlp).kernel("bias_grad_reduce")),
      abs_(ctx.program(programs::mlp).kernel("abs_f32")),
      scale_(ctx.program(programs::mlp).kernel("scale_f32")) {
  if (config_.inputs == 0 || config_.width == 0 || config_.outputs == 0)
    throw std::invalid_argument("mlp: inputs, width and outputs must be positive");
  std::size_t total = 0;
  for (std::size_t l = 0; l < layer_count(); ++l) {
    offsets_.push_back(total);
    total += fan_in(l) * fan_out(l) + fan_out(l);
  }
  offsets_.push_back(total);
  // config_.init's weights (and biases), the output layer's scaled by output_init.
  std::vector<float> host(total, 0.0f);
  std::mt19937_64 rng(seed);
  const bool torch = config_.init == WeightInit::Torch;
  for (std::size_t l = 0; l < layer_count(); ++l) {
    const float bound = float(std::sqrt((torch ? 1.0 : 6.0) / double(fan_in(l)))) *
                        (l + 1 == layer_count() ? config_.output_init : 1.0f);
    std::uniform_real_distribution<float> u(-bound, bound);
    const std::size_t weights = fan_in(l) * fan_out(l);
    for (std::size_t i = 0; i < weights + (torch ? fan_out(l) : 0); ++i) host[offsets_[l] + i] = u(rng);
  }
  params_ = cl::Buffer<float>(ctx, std::span<const float>(host));
  const auto& c = config_;
  if (c.small_path != MlpConfig::SmallPath::Layers && programs::mlp_fused_fits(c.width, c.hidden_layers, c.outputs) &&
      c.output_activation == OutputActivation::None) {
    const std::string options = programs::mlp_fused_options(unsigned(c.inputs), unsigned(c.width),
                                                            unsigned(c.hidden_layers), unsigned(c.outputs));
    auto& program = ctx.program(programs::mlp_fused, options);
    fused_.emplace(Fused{program.kernel("mlp_fused_forward"), program.kernel("mlp_fused_backward"),
                         program.kernel("mlp_fused_bias_reduce")});
  }
  grads_ = cl::Buffer<float>(ctx, total);
  grads_.fill(0.0f);
  if (fused_ && c.small_path == MlpConfig::SmallPath::Probe) {
    // A training forward and backward of a batch-sized input (as the I-Module's step runs them) on both paths.
    ProbeCache cache(ctx);
    const std::string shape = std::to_string(c.inputs) + "-" + std::to_string(c.width) + "x" +
                              std::to_string(c.hidden_layers) + "-" + std::to_string(c.outputs);
    constexpr std::size_t rows = 16384;
    std::optional<cl::Buffer<float>> x, dy;
    MlpContext probe;
    const auto time_of = [&] {
      if (!x) x.emplace(ctx, std::span<const float>(std::vector<float>(rows * c.inputs, 0.1f)));
      if (!dy) dy.emplace(ctx, std::span<const float>(std::vector<float>(rows * c.outputs, 0.01f)));
      return ProbeCache::time_best_of_three(ctx, [&] {
        forward_train(*x, rows, probe);
        backward(probe, *dy);
      });
    };
    const double fused_s = cache.seconds("mlp fused step " + shape, time_of);
    auto kept = std::move(fused_);
    fused_.reset();
    const double layers_s = cache.seconds("mlp layers step " + shape + " " + to_string(gemm.plan()), time_of);
    if (fused_s <= layers_s) fused_ = std::move(kept);
    grads_.fill(0.0f);  // the probe's backward passes accumulated into it
  }
}

std::size_t Mlp::fan_in(std::size_t layer) const { return layer == 0 ? config_.inputs : config_.width; }
std::size_t Mlp::fan_out(std::size_t layer) const {
  return layer == config_.hidden_layers ? config_.outputs : config_.width;
}

std::size_t Mlp::chunk_rows(std::size_t rows) const {
  const std::size_t widest = std::max({config_.inputs, config_.width, config_.outputs});
  const std::size_t by_alloc = ctx_->device().max_alloc_bytes / (sizeof(float) * widest);
  std::size_t c = std::min({rows, config_.max_chunk_rows, by_alloc});
  return std::max<std::size_t>(c, 1);
}

cl::Buffer<float>& Mlp::workspace(std::size_t i, std::size_t count) {
  // Fixed slots (resizing the vector would invalidate references callers hold): 0 dZ of the output layer,
  // 1-2 backward ping-pong, 3-4 inference ping-pong, 5 bias-gradient partial sums, 6-9 the fused backward's
  // hidden layers' dZ.
  if (workspace_.size() < 10) workspace_.resize(10);
  if (workspace_[i].size() < count) {
    workspace_[i] = cl::Buffer<float>();  // free before allocating: keeps the peak at one copy
    workspace_[i] = cl::Buffer<float>(*ctx_, count);
  }
  return workspace_[i];
}

void Mlp::forward_train(const cl::Buffer<float>& input, std::size_t rows, MlpContext& c) {
  const std::size_t H = config_.hidden_layers, W = config_.width, O = config_.outputs;
  const std::size_t chunk = chunk_rows(rows);
  const std::size_t chunks = (rows + chunk - 1) / chunk;
  const bool grow = c.chunk_rows < chunk || c.hidden.size() < chunks * H;
  if (grow) {
    c.hidden.clear();
    for (std::size_t i = 0; i < chunks * H; ++i) c.hidden.emplace_back(*ctx_, chunk * W);
    c.chunk_rows = chunk;
  }
  if (c.output.size() < rows * O) {
    c.output = cl::Buffer<float>();
    c.output = cl::Buffer<float>(*ctx_, rows * O);
  }
  const bool abs_out = config_.output_activation == OutputActivation::Abs;
  if (abs_out && c.pre_output.size() < rows * O) {
    c.pre_output = cl::Buffer<float>();
    c.pre_output = cl::Buffer<float>(*ctx_, rows * O);
  }
  c.rows = rows;
  c.input = &input;
  // Chunk boundaries follow c.chunk_rows (a reused context may have larger chunks than this batch needs).
  for (std::size_t r0 = 0, ci = 0; r0 < rows; r0 += c.chunk_rows, ++ci) {
    const std::size_t cr = std::min(c.chunk_rows, rows - r0);
    if (fused_) {
      fused_forward(input, r0, cr, c.output, r0, &c.hidden, ci * H);
      continue;
    }
    MatRef x = mat(input, config_.inputs, r0 * config_.inputs);
    for (std::size_t l = 0; l < H; ++l) {
      auto& y = c.hidden[ci * H + l];
      gemm_->run(Op::N, Op::N, cr, W, fan_in(l), 1.0f, x, mat(params_, W, weight_offset(l)), 0.0f, mat(y, W),
                 {&params_, bias_offset(l), Act::Relu});
      x = mat(y, W);
    }
    auto& out = abs_out ? c.pre_output : c.output;
    gemm_->run(Op::N, Op::N, cr, O, fan_in(H), 1.0f, x, mat(params_, O, weight_offset(H)), 0.0f, mat(out, O, r0 * O),
               {&params_, bias_offset(H), Act::None});
  }
  if (abs_out) abs_.args(u32(rows * O), c.pre_output, c.output, 0u).launch(rows * O);
}

void Mlp::fused_forward(const cl::Buffer<float>& input, std::size_t x_row, std::size_t rows, cl::Buffer<float>& out,
                        std::size_t out_row, const std::vector<cl::Buffer<float>>* hidden, std::size_t hidden_base) {
  const std::size_t H = config_.hidden_layers;
  auto h = [&](std::size_t l) -> const cl::Buffer<float>& {
    return hidden && l < H ? (*hidden)[hidden_base + l] : out;  // unused slots get any valid buffer
  };
  fused_->forward
      .args(u32(rows), input, u32(x_row), params_, out, u32(out_row), hidden ? 1u : 0u, h(0), h(1), h(2), h(3))
      .launch((rows + kFusedRows - 1) / kFusedRows, kFusedGroup);
}

MlpContext Mlp::forward_train(const cl::Buffer<float>& input, std::size_t rows) {
  MlpContext c;
  forward_train(input, rows, c);
  return c;
}

void Mlp::bias_grad(std::size_t rows, std::size_t cols, MatRef dy, const cl::Buffer<float>& saved, std::size_t s_off,
                    std::size_t s_ld, unsigned act, MatRef dz, std::size_t bias_off) {
  // 64 rows per work-item: a short second pass over the partial sums, enough work-items to fill the device.
  const std::size_t per_item = 64;
  const std::size_t groups = (rows + per_item - 1) / per_item;
  auto& partial = workspace(5, groups * cols);
  act_backward_
      .args(u32(rows), u32(cols), u32(per_item), *dy.buf, u32(dy.offset), u32(dy.ld), saved, u32(s_off), u32(s_ld), act,
            *dz.buf, u32(dz.offset), u32(dz.ld), partial)
      .launch({(cols + 15) / 16, groups}, {1, 16});
  bias_reduce_.args(u32(cols), u32(groups), partial, grads_, u32(bias_off)).launch(cols, 16);
}

void Mlp::backward(MlpContext& c, const cl::Buffer<float>& d_output, cl::Buffer<float>* d_input,
                   std::size_t d_input_cols) {
  if (!c.input) throw std::logic_error("mlp: backward without forward_train");
  const std::size_t H = config_.hidden_layers, W = config_.width, O = config_.outputs, I = config_.inputs;
  const bool abs_out = config_.output_activation == OutputActivation::Abs;
  if (fused_) {
    for (std::size_t r0 = 0, ci = 0; r0 < c.rows; r0 += c.chunk_rows, ++ci)
      fused_backward(c, r0, ci, std::min(c.chunk_rows, c.rows - r0), d_output, d_input, d_input_cols);
    return;
  }
  auto& dz_out = workspace(0, c.chunk_rows * O);
  for (std::size_t r0 = 0, ci = 0; r0 < c.rows; r0 += c.chunk_rows, ++ci) {
    const std::size_t cr = std::min(c.chunk_rows, c.rows - r0);
    auto x_of = [&](std::size_t l) { return l == 0 ? mat(*c.input, I, r0 * I) : mat(c.hidden[ci * H + l - 1], W); };
    // Output layer: dZ = dY ⊙ act'(z), db += Σ dZ, dW += Xᵀ·dZ, dX = dZ·Wᵀ.
    bias_grad(cr, O, mat(d_output, O, r0 * O), abs_out ? c.pre_output : d_output, r0 * O, O,
              abs_out ? kBwdAbs : kBwdNone, mat(dz_out, O), bias_offset(H));
    gemm_->run(Op::T, Op::N, fan_in(H), O, cr, 1.0f, x_of(H), mat(dz_out, O), 1.0f, mat(grads_, O, weight_offset(H)));
    MatRef dz = mat(dz_out, O);
    for (std::size_t l = H + 1; l-- > 0;) {
      const bool last = l == 0;
      if (last && !d_input) break;
      // dX of layer l is dY of layer l-1 (or dL/dinput); ping-pong between two workspaces.
      cl::Buffer<float>* dx_buf = last ? d_input : &workspace(1 + (l % 2), c.chunk_rows * W);
      const MatRef dx = last ? mat(*d_input, I, r0 * I) : mat(*dx_buf, W);
      const std::size_t cols = last && d_input_cols ? std::min(d_input_cols, I) : fan_in(l);
      gemm_->run(Op::N, Op::T, cr, cols, fan_out(l), 1.0f, dz, mat(params_, fan_out(l), weight_offset(l)), 0.0f, dx);
      if (last) break;
      // Hidden layer l-1: ReLU mask from its saved output, in place.
      const std::size_t h = l - 1;
      bias_grad(cr, W, dx, c.hidden[ci * H + h], 0, W, kBwdRelu, dx, bias_offset(h));
      gemm_->run(Op::T, Op::N, fan_in(h), W, cr, 1.0f, x_of(h), dx, 1.0f, mat(grads_, W, weight_offset(h)));
      dz = dx;
    }
  }
}

void Mlp::fused_backward(MlpContext& c, std::size_t r0, std::size_t ci, std::size_t rows,
                         const cl::Buffer<float>& d_output, cl::Buffer<float>* d_input, std::size_t d_input_cols) {
  const std::size_t H = config_.hidden_layers, W = config_.width, O = config_.outputs, I = config_.inputs;
  const std::size_t items = (rows + kFusedRows - 1) / kFusedRows, groups = (items + kFusedGroup - 1) / kFusedGroup;
  const std::size_t bias_cols = H * W + O;
  auto& partial = workspace(5, groups * bias_cols);
  // Each hidden layer's dZ in slots 6.. (workspace()'s fixed slots), the same chunk rows as the saved activations.
  auto dz = [&](std::size_t l) -> cl::Buffer<float>& { return workspace(6 + std::min(l, H - 1), c.chunk_rows * W); };
  auto saved = [&](std::size_t l) -> const cl::Buffer<float>& { return c.hidden[ci * H + std::min(l, H - 1)]; };
  const std::size_t cols = d_input ? (d_input_cols ? std::min(d_input_cols, I) : I) : 0;
  fused_->backward
      .args(u32(rows), d_output, u32(r0), params_, saved(0), saved(1), saved(2), saved(3), dz(0), dz(1), dz(2), dz(3),
            u32(cols), d_input ? *d_input : d_output, u32(r0), partial)
      .launch(groups * kFusedGroup, kFusedGroup);
  // dW_l += X_lᵀ · dZ_l, X_l the layer's input (the batch's input or the previous hidden layer's output).
  gemm_->run(Op::T, Op::N, W, O, rows, 1.0f, mat(saved(H - 1), W), mat(d_output, O, r0 * O), 1.0f,
             mat(grads_, O, weight_offset(H)));
  for (std::size_t l = 0; l < H; ++l) {
    const MatRef x = l == 0 ? mat(*c.input, I, r0 * I) : mat(saved(l - 1), W);
    gemm_->run(Op::T, Op::N, fan_in(l), W, rows, 1.0f, x, mat(dz(l), W), 1.0f, mat(grads_, W, weight_offset(l)));
  }
  fused_->bias_reduce.args(u32(groups), partial, grads_).launch(bias_cols, kFusedGroup);
}

void Mlp::infer(const cl::Buffer<float>& input, std::size_t rows, cl::Buffer<float>& output, std::size_t out_row) {
  const std::size_t H = config_.hidden_layers, W = config_.width, O = config_.outputs;
  const std::size_t chunk = chunk_rows(rows);
  for (std::size_t r0 = 0; r0 < rows; r0 += chunk) {
    const std::size_t cr = std::min(chunk, rows - r0);
    if (fused_) {
      fused_forward(input, r0, cr, output, out_row + r0, nullptr, 0);
      continue;
    }
    MatRef x = mat(input, config_.inputs, r0 * config_.inputs);
    for (std::size_t l = 0; l < H; ++l) {
      auto& y = workspace(3 + (l % 2), chunk * W);
      gemm_->run(Op::N, Op::N, cr, W, fan_in(l), 1.0f, x, mat(params_, W, weight_offset(l)), 0.0f, mat(y, W),
                 {&params_, bias_offset(l), Act::Relu});
      x = mat(y, W);
    }
    gemm_->run(Op::N, Op::N, cr, O, fan_in(H), 1.0f, x, mat(params_, O, weight_offset(H)), 0.0f,
               mat(output, O, (out_row + r0) * O), {&params_, bias_offset(H), Act::None});
  }
  if (config_.output_activation == OutputActivation::Abs)
    abs_.args(u32(rows * O), output, output, u32(out_row * O)).launch(rows * O);
  if (config_.output_scale != 1.0f)
    scale_.args(u32(rows * O), config_.output_scale, output, u32(out_row * O)).launch(rows * O);
}

}  // namespace clr::nn
