// The residual loss and its gradient w.r.t. the prediction, summed over n elements. Needs atomics.cl before it.
//   r² / (sg(pred)² + 0.01)^power            dL/dpred = 2r / (sg(pred)² + 0.01)^power
// with r = pred − target_scale·target and sg a stop-gradient (the denominator is a constant): power 0 is L2, 1
// relative L2. target_scale puts the target in the prediction's units (nn/loss.hpp). `scale`
// (e.g. 1/n for a mean) multiplies both the loss and the gradient. Elements whose loss or gradient is not finite are
// dropped (gradient 0, no loss) and counted (docs/design.md §7). The group size must be a power of two (tree
// reduction); every work-item reaches every barrier.
__kernel void loss_l2(uint n, __global const float* pred, __global const float* target, float target_scale, float scale,
                      float power, __global float* grad, volatile __global float* total,
                      volatile __global uint* non_finite, __local float* scratch) {
  const uint i = (uint)get_global_id(0);
  float l = 0.0f;
  if (i < n) {
    const float p = pred[i];
    const float r = p - target_scale * target[i];
    const float den = pow(p * p + 0.01f, power);  // pow(x, 0) = 1 exactly
    l = scale * (r * r / den);
    float g = scale * (2.0f * r / den);
    if (!isfinite(l) || !isfinite(g)) {
      atomic_inc(non_finite);
      l = 0.0f;
      g = 0.0f;
    }
    grad[i] = g;
  }
  group_add_f32(total, l, scratch);
}
