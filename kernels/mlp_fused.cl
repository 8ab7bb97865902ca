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
