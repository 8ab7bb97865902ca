// Element-wise parts of dense layers that the GEMM does not fuse.
#define BWD_NONE 0
#define BWD_RELU 1  // saved = post-activation output y; relu'(z) = (y > 0)
#define BWD_ABS 2   // saved = pre-activation z; d|z|/dz = sign(z) (0 at 0, as PyTorch's abs)

// dZ = dY ⊙ act'(saved) over rows × cols (dZ may alias dY), and the column sums of dZ in two deterministic passes:
// work-item (c, g) walks rows [g·rows_per_item, …) of column c (adjacent work-items touch adjacent columns, so
// loads coalesce on GPUs) and writes its partial sum to partial[g·cols + c]; bias_grad_reduce then adds the
// partials in a fixed order. No float atomics here, so an MLP step is bit-reproducible on a given device.
__kernel void act_backward_bias_grad(uint rows, uint cols, uint rows_per_item, __global const float* dY, uint dy_off,
                                     uint dy_ld, __global const float* saved, uint s_off, uint s_ld, uint act,
                                     __global float* dZ, uint dz_off, uint dz_ld, __global float* partial) {
  const uint c = (uint)get_global_id(0);
  const uint r0 = (uint)get_global_id(1) * rows_per_item;
  if (c >= cols || r0 >= rows) return;
  const uint r1 = min(rows, r0 + rows_per_item);
  float sum = 0.0f;
  for (uint r = r0; r < r1; ++r) {
    float d = dY[dy_off + r * dy_ld + c];
    if (act == BWD_RELU) {
      d = saved[s_off + r * s_ld + c] > 0.0f ? d : 0.0f;
    } else if (act == BWD_ABS) {
      const float z = saved[s_off + r * s_ld + c];
      d = z > 0.0f ? d : (z < 0.0f ? -d : 0.0f);
    }
    dZ[dz_off + r * dz_ld + c] = d;
    sum += d;
  }
  partial[get_global_id(1) * cols + c] = sum;
}

// db[db_off + c] += Σ_g partial[g·cols + c], g in order.
__kernel void bias_grad_reduce(uint cols, uint groups, __global const float* partial, __global float* db, uint db_off) {
  const uint c = (uint)get_global_id(0);
  if (c >= cols) return;
  float s = 0.0f;
  for (uint g = 0; g < groups; ++g) s += partial[g * cols + c];
  db[db_off + c] += s;
}

// out[off + i] = |in[off + i]| for i < n.
__kernel void abs_f32(uint n, __global const float* in, __global float* out, uint off) {
  const uint i = (uint)get_global_id(0);
  if (i < n) out[off + i] = fabs(in[off + i]);
}
