#pragma once
// The residual loss of training (docs/design.md §2), r² / (sg(pred)² + 0.01)^power — power 0 is L2, 1 relative L2 —
// with its gradient w.r.t. the prediction. Non-finite elements are dropped and counted.
#include <cstdint>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"

namespace clr::nn {

struct LossValue {
  double loss;               // Σ scale · loss over the finite elements
  std::uint32_t non_finite;  // elements dropped
};

class Loss {
 public:
  explicit Loss(cl::Context& ctx);
  // grad[i] = scale · dL/dpred[i] for i < n; enqueues only (no sync), accumulating into the running value.
  // `target_scale` multiplies the target first: a network trained in units of its output scale s
  // (NetworkConfig::output_scale) compares its raw output with target / s, so the 0.01 is 0.01·s² in radiance.
  void evaluate(const cl::Buffer<float>& pred, const cl::Buffer<float>& target, std::size_t n, float scale, float power,
                cl::Buffer<float>& grad, float target_scale = 1.0f);
  // Reads and resets the accumulated value (a sync point: call it only when the value is needed).
  LossValue take();

 private:
  cl::Buffer<float> total_;
  cl::Buffer<std::uint32_t> non_finite_;
  cl::Kernel kernel_;
};

}  // namespace clr::nn
