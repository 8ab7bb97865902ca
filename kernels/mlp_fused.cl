// A whole small MLP (width ≤ 64: the I-Module's 3 × 64 → 32) in one launch: each work-item keeps RPI rows'
// activations in private memory from the input to the output, so no activation round-trips through global memory
// between layers and there is one launch instead of one per layer. Weights (≈ 58 KB for the I-Module) are read
// from global memory and stay in cache.
// Compile-time shape: IN inputs, WIDTH (multiple of 16), HIDDEN layers (1..4), OUT outputs (multiple of 16).
// Parameter layout as nn::Mlp: per layer W [fan_in × fan_out] row-major, then b [fan_out].
// With save_hidden, hidden layer l's output goes to H<l> ([rows × WIDTH]) for the generic backward pass.
#define RPI 4
#define WV (WIDTH / 16)
#define OV (OUT / 16)

// acc[r][v] = bias + Σ_i x[r][i] · W[i][16v .. 16v+15] for an input of `fan_in` values per row.
#define DENSE(acc, NVEC, fan_out, x_at, fan_in, w, b)                                                            \
  _Pragma("unroll") for (uint r = 0; r < RPI; ++r) _Pragma("unroll") for (uint v = 0; v < NVEC; ++v) acc[r][v] = \
      vload16(v, b);                                                                                             \
  for (uint i = 0; i < fan_in; ++i) {                                                                            \
    __global const float* wrow = w + i * fan_out;                                                                \
    float16 wv[NVEC];                                                                                            \
    _Pragma("unroll") for (uint v = 0; v < NVEC; ++v) wv[v] = vload16(v, wrow);                                  \
    _Pragma("unroll") for (uint r = 0; r < RPI; ++r) {                                                           \
      const float16 a = (float16)(x_at);                                                                         \
      _Pragma("unroll") for (uint v = 0; v < NVEC; ++v) acc[r][v] = fma(a, wv[v], acc[r][v]);                    \
    }                                                                                                            \
  }

__kernel void mlp_fused_forward(uint rows, __global const float* X, uint x_row, __global const float* P,
                                __global float* Y, uint y_off, uint save_hidden, __global float* H0, __global float* H1,
                                __global float* H2, __global float* H3) {
  const uint row0 = (uint)get_global_id(0) * RPI;
  if (row0 >= rows) return;
  uint rr[RPI];  // rows past the end recompute the last row and are not stored
  for (uint r = 0; r < RPI; ++r) rr[r] = min(row0 + r, rows - 1);
  float h[RPI][WIDTH];
  float16 acc[RPI][WV];
  uint off = 0;
  __global float* saved[4] = {H0, H1, H2, H3};
  for (uint l = 0; l < HIDDEN; ++l) {
    const uint fan_in = l == 0 ? IN : WIDTH;
    __global const float* w = P + off;
    __global const float* b = w + fan_in * WIDTH;
    if (l == 0) {
      DENSE(acc, WV, WIDTH, X[(x_row + rr[r]) * IN + i], IN, w, b)
    } else {
      DENSE(acc, WV, WIDTH, h[r][i], WIDTH, w, b)
    }
    for (uint r = 0; r < RPI; ++r)
      for (uint v = 0; v < WV; ++v) {
        const float16 y = fmax(acc[r][v], (float16)(0.0f));
        vstore16(y, v, h[r]);
        if (save_hidden && row0 + r < rows) vstore16(y, v, saved[l] + (row0 + r) * WIDTH);
      }
    off += fan_in * WIDTH + WIDTH;
  }
  float16 out[RPI][OV];
  __global const float* w = P + off;
  __global const float* b = w + WIDTH * OUT;
  DENSE(out, OV, OUT, h[r][i], WIDTH, w, b)
  for (uint r = 0; r < RPI; ++r)
    if (row0 + r < rows)
      for (uint v = 0; v < OV; ++v) vstore16(out[r][v], v, Y + (y_off + row0 + r) * OUT);
}

// The backward pass of the same network in one launch, the counterpart of mlp_fused_forward: each work-item carries
// its RPI rows' dZ from the output back to the input in private memory — dX = dZ·Wᵀ, masked by ReLU' from the
// saved hidden outputs — so the per-layer dX GEMMs and element-wise passes become one launch. It writes each hidden
// layer's dZ (D<l>, [rows × WIDTH]) for the host's dW = Xᵀ·dZ GEMMs, dL/dinput's first `d_input_cols` columns where
// asked, and per work-group the column sums of every layer's dZ (the bias gradients) to partial[group · BIAS_COLS
// + column], hidden layers first, then the output layer's; mlp_fused_bias_reduce adds those in a fixed order, so
// the step stays bit-reproducible (no atomics). Launch with a local size of GROUP.
#define GROUP 16
#define BIAS_COLS (HIDDEN * WIDTH + OUT)
#define MAXW (WIDTH > OUT ? WIDTH : OUT)

// Offset of layer l's weights in P (nn::Mlp::weight_offset); its bias follows its fan_in × fan_out weights.
inline uint layer_offset(uint l) { return l == 0 ? 0u : IN * WIDTH + WIDTH + (l - 1) * (WIDTH * WIDTH + WIDTH); }

inline float hsum16(float16 v) {
  const float8 a = v.lo + v.hi;
  const float4 b = a.lo + a.hi;
  const float2 c = b.lo + b.hi;
  return c.x + c.y;
}

// The work-group's column sums of d[RPI][MAXW]'s first n columns into part[0 .. n). Rows past the batch hold zeros.
inline void group_column_sums(float d[RPI][MAXW], uint n, __local float* scratch, __global float* part) {
  const uint t = (uint)get_local_id(0);
  for (uint c = 0; c < n; ++c) {
    float s = 0.0f;
    _Pragma("unroll") for (uint r = 0; r < RPI; ++r) s += d[r][c];
    scratch[t * MAXW + c] = s;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint c = t; c < n; c += GROUP) {
    float s = 0.0f;
    for (uint i = 0; i < GROUP; ++i) s += scratch[i * MAXW + c];
    part[c] = s;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

__kernel void mlp_fused_backward(uint rows, __global const float* dY, uint dy_row, __global const float* P,
                                 __global const float* H0, __global const float* H1, __global const float* H2,
                                 __global const float* H3, __global float* D0, __global float* D1, __global float* D2,
                                 __global float* D3, uint d_input_cols, __global float* dX, uint dx_row,
                                 __global float* partial) {
  __local float scratch[GROUP * MAXW];
  const uint row0 = (uint)get_global_id(0) * RPI;
  __global const float* saved[4] = {H0, H1, H2, H3};
  __global float* dz_out[4] = {D0, D1, D2, D3};
  __global float* part = partial + get_group_id(0) * BIAS_COLS;
  // Every work-item reaches the barriers: rows past the end read the last row's activations and carry dZ = 0.
  uint rr[RPI];
  bool live[RPI];
  for (uint r = 0; r < RPI; ++r) {
    live[r] = row0 + r < rows;
    rr[r] = min(row0 + r, rows - 1);
  }
  float d[RPI][MAXW], x[RPI][WIDTH];  // d: a layer's dZ (OUT wide at the output); x: the next one's dY
  for (uint r = 0; r < RPI; ++r)
    for (uint v = 0; v < OV; ++v)
      vstore16(live[r] ? vload16(v, dY + (dy_row + rr[r]) * OUT) : (float16)(0.0f), v, d[r]);
  group_column_sums(d, OUT, scratch, part + HIDDEN * WIDTH);
  for (uint l = HIDDEN + 1; l-- > 0;) {
    // d holds layer l's dZ; x = dZ · W_lᵀ is layer l−1's dY (or dL/dinput).
    if (l == 0 && d_input_cols == 0) break;
    const uint fan_out = l == HIDDEN ? OUT : WIDTH;
    const uint cols = l == 0 ? d_input_cols : WIDTH;
    __global const float* w = P + layer_offset(l);
    for (uint i = 0; i < cols; ++i) {
      __global const float* wrow = w + i * fan_out;
      _Pragma("unroll") for (uint r = 0; r < RPI; ++r) {
        float16 acc = (float16)(0.0f);
        for (uint v = 0; v < fan_out / 16; ++v) acc = fma(vload16(v, d[r]), vload16(v, wrow), acc);
        if (l > 0)
          x[r][i] = hsum16(acc);
        else if (live[r])  // dL/dinput goes straight out: IN may exceed the private rows' width
          dX[(dx_row + row0 + r) * IN + i] = hsum16(acc);
      }
    }
    if (l == 0) break;
    __global const float* h = saved[l - 1];
    for (uint r = 0; r < RPI; ++r)
      for (uint v = 0; v < WV; ++v) {
        const float16 dz = select((float16)(0.0f), vload16(v, x[r]), vload16(v, h + rr[r] * WIDTH) > 0.0f);
        vstore16(dz, v, d[r]);
        if (live[r]) vstore16(dz, v, dz_out[l - 1] + (row0 + r) * WIDTH);
      }
    group_column_sums(d, WIDTH, scratch, part + (l - 1) * WIDTH);
  }
}

// grads[bias of the column's layer] += Σ_g partial[g · BIAS_COLS + c], g in order.
__kernel void mlp_fused_bias_reduce(uint groups, __global const float* partial, __global float* grads) {
  const uint c = (uint)get_global_id(0);
  if (c >= BIAS_COLS) return;
  float s = 0.0f;
  for (uint g = 0; g < groups; ++g) s += partial[g * BIAS_COLS + c];
  const uint l = min(c / WIDTH, (uint)HIDDEN), j = c - l * WIDTH;
  const uint fan_in = l == 0 ? IN : WIDTH, fan_out = l == HIDDEN ? OUT : WIDTH;
  grads[layer_offset(l) + fan_in * fan_out + j] += s;
}
