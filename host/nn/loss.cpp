#include "nn/loss.hpp"

#include "nn/gemm.hpp"
#include "nn/programs.hpp"

namespace clr::nn {

Loss::Loss(cl::Context& ctx)
    : total_(ctx, 1), non_finite_(ctx, 1), kernel_(ctx.program(programs::loss).kernel("loss_l2")) {
  total_.fill(0.0f);
  non_finite_.fill(0u);
}

void Loss::evaluate(const cl::Buffer<float>& pred, const cl::Buffer<float>& target, std::size_t n, float scale,
                    float power, cl::Buffer<float>& grad, float target_scale) {
  constexpr std::size_t local = 64;  // a power of two: the kernel's tree reduction needs one
  kernel_
      .args(u32(n), pred, target, target_scale, scale, power, grad, total_, non_finite_,
            cl::LocalMemory{local * sizeof(float)})
      .launch(n, local);
}

LossValue Loss::take() {
  LossValue v{double(total_.read()[0]), non_finite_.read()[0]};
  total_.fill(0.0f);
  non_finite_.fill(0u);
  return v;
}

}  // namespace clr::nn
