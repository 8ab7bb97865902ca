#pragma once
// Adam over one flat parameter buffer (one launch per network), with decoupled weight decay and a learning-rate
// schedule: lr(t) = lr · decay^floor(max(0, t − decay_start) / decay_interval) (constant when decay == 1).
#include <cstdint>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"

namespace clr::nn {

struct AdamConfig {
  float learning_rate = 5e-3f;  // ISNR §4.3
  float beta1 = 0.9f;
  float beta2 = 0.999f;
  float epsilon = 1e-8f;
  float weight_decay = 0.0f;
  float decay = 1.0f;  // multiplicative learning-rate decay per interval
  std::uint64_t decay_start = 0;
  std::uint64_t decay_interval = 1000;

  float learning_rate_at(std::uint64_t step) const;  // step counts from 1
};

class Adam {
 public:
  Adam(cl::Context& ctx, std::size_t count, AdamConfig config);

  // One update of `params` from `grads` (which it zeroes). Dense: every element.
  void step(cl::Buffer<float>& params, cl::Buffer<float>& grads);
  // Lazy update of a table of `touched.size()` entries × `features` floats: only entries whose flag is set.
  void step_sparse(cl::Buffer<float>& params, cl::Buffer<float>& grads, cl::Buffer<std::uint8_t>& touched,
                   std::size_t features);
  // The same with an int64 fixed-point gradient in units of 2^-40 (the hash grid's deterministic mode).
  void step_sparse_fixed(cl::Buffer<float>& params, cl::Buffer<std::int64_t>& grads, cl::Buffer<std::uint8_t>& touched,
                         std::size_t features);

  std::uint64_t steps() const { return steps_; }
  void set_steps(std::uint64_t s) { steps_ = s; }
  // A factor on the configured learning rate from the next step on (a trainer's budget-driven annealing).
  void set_learning_rate_scale(float s) { lr_scale_ = s; }
  const AdamConfig& config() const { return config_; }
  cl::Buffer<float>& first_moment() { return m_; }
  cl::Buffer<float>& second_moment() { return v_; }
  const cl::Buffer<float>& first_moment() const { return m_; }
  const cl::Buffer<float>& second_moment() const { return v_; }
  // Gradient values dropped as non-finite since construction (reads the device counter: a sync point).
  std::uint32_t non_finite_gradients() const { return non_finite_.read()[0]; }

 private:
  void advance(float& lr, float& c1, float& c2);
  template <typename G>
  void step_table(cl::Kernel& kernel, cl::Buffer<float>& params, cl::Buffer<G>& grads,
                  cl::Buffer<std::uint8_t>& touched, std::size_t features);

  cl::Context* ctx_;
  AdamConfig config_;
  std::uint64_t steps_ = 0;
  float lr_scale_ = 1.0f;
  cl::Buffer<float> m_, v_;
  cl::Buffer<std::uint32_t> non_finite_;
  cl::Kernel dense_, sparse_, sparse_fixed_;
};

}  // namespace clr::nn
