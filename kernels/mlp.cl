// Element-wise parts of dense layers that the GEMM does not fuse.
#define BWD_NONE 0
#define BWD_RELU 1  // saved = post-activation output y; relu'(z) = (y > 0)
#define BWD_ABS 2   // saved = pre-activation z; d|z|/dz = sign(z) (0 at 0, as PyTorch's abs)

// dZ = dY ⊙ act'(saved) over rows × cols (dZ may alias dY), and the column sums of dZ in two deterministic passes:
// work-item (16-column chunk c0, row group g) walks rows [g·rows_per_item, …) loading 16 contiguous floats per row
// (one cache line on a CPU, a coalesced run across a GPU warp) and writes its partial sums to partial[g·cols + c];
// bias_grad_reduce then adds the partials in a fixed order. No float atomics here, so an MLP step is
// bit-reproducible on a given device. (Walking one column per work-item instead strides through memory a row
// apart for every element and was far slower on the CPU device: docs/results/benchmarks.md.)
inline float16 act_grad16(float16 d, float16 s, uint act) {
  if (act == BWD_RELU) return select((float16)(0.0f), d, s > 0.0f);
  if (act == BWD_ABS) return select(select((float16)(0.0f), -d, s < 0.0f), d, s > 0.0f);
  return d;
}

inline float act_grad1(float d, float s, uint act) {
  if (act == BWD_RELU) return s > 0.0f ? d : 0.0f;
  if (act == BWD_ABS) return s > 0.0f ? d : (s < 0.0f ? -d : 0.0f);
  return d;
}

__kernel void act_backward_bias_grad(uint rows, uint cols, uint rows_per_item, __global const float* dY, uint dy_off,
                                     uint dy_ld, __global const float* saved, uint s_off, uint s_ld, uint act,
                                     __global float* dZ, uint dz_off, uint dz_ld, __global float* partial) {
  const uint c0 = (uint)get_global_id(0) * 16;
  const uint r0 = (uint)get_global_id(1) * rows_per_item;
  if (c0 >= cols || r0 >= rows) return;
  const uint r1 = min(rows, r0 + rows_per_item);
  __global float* p = partial + get_global_id(1) * cols + c0;
  if (c0 + 16 <= cols) {
    float16 sum = (float16)(0.0f);
    for (uint r = r0; r < r1; ++r) {
      const float16 s = act == BWD_NONE ? (float16)(0.0f) : vload16(0, saved + s_off + r * s_ld + c0);
      const float16 d = act_grad16(vload16(0, dY + dy_off + r * dy_ld + c0), s, act);
      vstore16(d, 0, dZ + dz_off + r * dz_ld + c0);
      sum += d;
    }
    vstore16(sum, 0, p);
  } else {
    for (uint c = c0; c < cols; ++c) {
      float sum = 0.0f;
      for (uint r = r0; r < r1; ++r) {
        const float s = act == BWD_NONE ? 0.0f : saved[s_off + r * s_ld + c];
        const float d = act_grad1(dY[dy_off + r * dy_ld + c], s, act);
        dZ[dz_off + r * dz_ld + c] = d;
        sum += d;
      }
      p[c - c0] = sum;
    }
  }
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

// x[off + i] *= s for i < n (an output scale, nn/network.hpp).
__kernel void scale_f32(uint n, float s, __global float* x, uint off) {
  const uint i = (uint)get_global_id(0);
  if (i < n) x[off + i] *= s;
}

// out[off + r·C + c] = in[off + r·C + c] · max(raw[(row0 + r)·ld + col + c], floor_) for r < rows, c < C: a network
// whose output is a factor of the surface's albedo (NetworkConfig::albedo_factor); in and out may be one buffer.
__kernel void albedo_factor(uint rows, uint C, __global const float* raw, uint row0, uint ld, uint col, float floor_,
                            __global const float* in, __global float* out, uint off) {
  const uint i = (uint)get_global_id(0);
  if (i >= rows * C) return;
  const uint r = i / C, c = i - r * C;
  out[off + i] = in[off + i] * fmax(raw[(row0 + r) * ld + col + c], floor_);
}
