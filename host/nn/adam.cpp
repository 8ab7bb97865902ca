#include "nn/adam.hpp"

#include <cmath>
#include <stdexcept>

#include "nn/gemm.hpp"
#include "nn/programs.hpp"

namespace clr::nn {

float AdamConfig::learning_rate_at(std::uint64_t step) const {
  if (decay == 1.0f || step <= decay_start) return learning_rate;
  const auto intervals = double((step - decay_start) / std::max<std::uint64_t>(decay_interval, 1));
  return float(double(learning_rate) * std::pow(double(decay), intervals));
}

Adam::Adam(cl::Context& ctx, std::size_t count, AdamConfig config)
    : ctx_(&ctx),
      config_(config),
      m_(ctx, count),
      v_(ctx, count),
      non_finite_(ctx, 1),
      dense_(ctx.program(programs::adam).kernel("adam_step")),
      sparse_(ctx.program(programs::adam).kernel("adam_step_sparse")),
      sparse_fixed_(ctx.program(programs::adam).kernel("adam_step_sparse_fixed")) {
  m_.fill(0.0f);
  v_.fill(0.0f);
  non_finite_.fill(0u);
}

void Adam::advance(float& lr, float& c1, float& c2) {
  ++steps_;
  const double t = double(steps_);
  lr = lr_scale_ * config_.learning_rate_at(steps_);
  c1 = float(1.0 / (1.0 - std::pow(double(config_.beta1), t)));
  c2 = float(1.0 / (1.0 - std::pow(double(config_.beta2), t)));
}

void Adam::step(cl::Buffer<float>& params, cl::Buffer<float>& grads) {
  if (params.size() != m_.size() || grads.size() != m_.size())
    throw std::logic_error("adam: parameter, gradient and moment buffers differ in size");
  float lr, c1, c2;
  advance(lr, c1, c2);
  dense_
      .args(u32(params.size()), params, grads, m_, v_, lr, config_.beta1, config_.beta2, config_.epsilon,
            config_.weight_decay, c1, c2, non_finite_)
      .launch(params.size(), 64);
}

template <typename G>
void Adam::step_table(cl::Kernel& kernel, cl::Buffer<float>& params, cl::Buffer<G>& grads,
                      cl::Buffer<std::uint8_t>& touched, std::size_t features) {
  if (params.size() != m_.size() || grads.size() != m_.size() || touched.size() * features != params.size())
    throw std::logic_error("adam: table, gradient, moment and touched-flag sizes disagree");
  float lr, c1, c2;
  advance(lr, c1, c2);
  kernel
      .args(u32(touched.size()), u32(features), touched, params, grads, m_, v_, lr, config_.beta1, config_.beta2,
            config_.epsilon, config_.weight_decay, c1, c2, non_finite_)
      .launch(touched.size(), 64);
}

void Adam::step_sparse(cl::Buffer<float>& params, cl::Buffer<float>& grads, cl::Buffer<std::uint8_t>& touched,
                       std::size_t features) {
  step_table(sparse_, params, grads, touched, features);
}

void Adam::step_sparse_fixed(cl::Buffer<float>& params, cl::Buffer<std::int64_t>& grads,
                             cl::Buffer<std::uint8_t>& touched, std::size_t features) {
  step_table(sparse_fixed_, params, grads, touched, features);
}

}  // namespace clr::nn
