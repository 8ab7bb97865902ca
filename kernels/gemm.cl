// Register-blocked GEMM without local memory: C = act(alpha · op(A) · B + beta · C + bias).
//
// Each work-item owns a TM × (VW·NV) tile of C and keeps it in vector registers for the whole k loop; B rows are
// loaded as VW-wide vectors and every A element is broadcast into TM·NV fused multiply-adds. On PoCL's CPU device
// the defaults (8 rows × 2 float16 = 8 × 32 outputs, 16 zmm accumulators) reach 130-160 GFLOP/s where CLBlast's
// untuned kernels reach 8-28 (DESIGN.md §6). GPUs get smaller tiles through the same defines (TM, VW, NV).
//
// op(A) is addressed through strides, so A and Aᵀ cost the same: op(A)(m, k) = A[a_off + m·a_rs + k·a_cs].
// B must be row-major [K × N] with unit column stride (the host transposes B when op(B) = Bᵀ).
// Split-K: the k range is cut into slices of k_slice; slice s writes its tile to C + s·c_slice (the host passes a
// scratch buffer, alpha = 1, beta = 0, then gemm_reduce_slices sums them). With one slice, c_slice = 0.
#ifndef TM
#define TM 8
#endif
#ifndef VW
#define VW 16
#endif
#ifndef NV
#define NV 2
#endif
#define TN (VW * NV)
#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define floatV CAT(float, VW)
#define vloadV CAT(vload, VW)
#define vstoreV CAT(vstore, VW)

#define ACT_NONE 0
#define ACT_RELU 1

inline float apply_act(float x, uint act) { return act == ACT_RELU ? fmax(x, 0.0f) : x; }

inline floatV apply_act_v(floatV x, uint act) { return act == ACT_RELU ? fmax(x, (floatV)(0.0f)) : x; }

__kernel void gemm_own(uint M, uint N, uint K, float alpha, __global const float* A, uint a_off, uint a_rs, uint a_cs,
                       __global const float* B, uint b_off, uint ldb, float beta, __global float* C, uint c_off,
                       uint ldc, uint k_slice, uint c_slice, __global const float* bias, uint bias_off, uint use_bias,
                       uint act) {
  const uint tiles_m = (M + TM - 1) / TM;
  const uint n0 = (uint)get_global_id(0) * TN;
  const uint gm = (uint)get_global_id(1);
  const uint slice = gm / tiles_m;
  const uint m0 = (gm - slice * tiles_m) * TM;
  const uint kb = slice * k_slice;
  if (n0 >= N || m0 >= M || kb >= K) return;  // padding work-items; no barriers in this kernel
  const uint ke = min(K, kb + k_slice);
  __global float* Cs = C + c_off + slice * c_slice;

  if (m0 + TM <= M && n0 + TN <= N) {
    floatV acc[TM][NV];
#pragma unroll
    for (uint i = 0; i < TM; ++i)
#pragma unroll
      for (uint v = 0; v < NV; ++v) acc[i][v] = (floatV)(0.0f);
    __global const float* ap = A + a_off + m0 * a_rs + kb * a_cs;
    __global const float* bp = B + b_off + kb * ldb + n0;
    for (uint k = kb; k < ke; ++k) {
      floatV b[NV];
#pragma unroll
      for (uint v = 0; v < NV; ++v) b[v] = vloadV(v, bp);
#pragma unroll
      for (uint i = 0; i < TM; ++i) {
        const floatV a = (floatV)(ap[i * a_rs]);
#pragma unroll
        for (uint v = 0; v < NV; ++v) acc[i][v] = fma(a, b[v], acc[i][v]);
      }
      ap += a_cs;
      bp += ldb;
    }
#pragma unroll
    for (uint i = 0; i < TM; ++i) {
      __global float* cp = Cs + (m0 + i) * ldc + n0;
#pragma unroll
      for (uint v = 0; v < NV; ++v) {
        floatV r = alpha * acc[i][v];
        // beta == 0 must not read C: it may hold garbage (or NaN) that 0·C would propagate.
        if (beta != 0.0f) r += beta * vloadV(v, cp);
        if (use_bias) r += vloadV(v, bias + bias_off + n0);
        vstoreV(apply_act_v(r, act), v, cp);
      }
    }
  } else {
    // Edge tile: fewer rows or columns than a full tile. Scalar, with the column loop bounded at run time so
    // narrow matrices (the 3-wide output layer) do not pay for a full TN-wide tile.
    const uint mm = min((uint)TM, M - m0);
    const uint nn = min((uint)TN, N - n0);
    float acc[TM * TN];
    for (uint i = 0; i < TM * TN; ++i) acc[i] = 0.0f;
    for (uint k = kb; k < ke; ++k) {
      __global const float* brow = B + b_off + k * ldb + n0;
      for (uint i = 0; i < mm; ++i) {
        const float a = A[a_off + (m0 + i) * a_rs + k * a_cs];
        for (uint j = 0; j < nn; ++j) acc[i * TN + j] = fma(a, brow[j], acc[i * TN + j]);
      }
    }
    for (uint i = 0; i < mm; ++i)
      for (uint j = 0; j < nn; ++j) {
        __global float* cp = Cs + (m0 + i) * ldc + n0 + j;
        float r = alpha * acc[i * TN + j];
        if (beta != 0.0f) r += beta * *cp;
        if (use_bias) r += bias[bias_off + n0 + j];
        *cp = apply_act(r, act);
      }
  }
}

// C = alpha · Σ_s P[s] + beta · C over `slices` partial products of M × N (row-major, P packed, C with ldc).
__kernel void gemm_reduce_slices(uint M, uint N, uint slices, __global const float* P, float alpha, float beta,
                                 __global float* C, uint c_off, uint ldc) {
  const uint j = (uint)get_global_id(0);
  const uint i = (uint)get_global_id(1);
  if (i >= M || j >= N) return;
  float s = 0.0f;
  for (uint t = 0; t < slices; ++t) s += P[(t * M + i) * N + j];
  __global float* cp = C + c_off + i * ldc + j;
  float r = alpha * s;
  if (beta != 0.0f) r += beta * *cp;
  *cp = r;
}

// out[cols × rows] = in[rows × cols]ᵀ (in with leading dimension ld, out packed).
__kernel void transpose(uint rows, uint cols, __global const float* in, uint in_off, uint ld, __global float* out) {
  const uint j = (uint)get_global_id(0);
  const uint i = (uint)get_global_id(1);
  if (i >= rows || j >= cols) return;
  out[j * rows + i] = in[in_off + i * ld + j];
}

// Y = act(Y + bias) in place over rows × cols (ld), for backends whose GEMM has no fused epilogue (CLBlast).
__kernel void bias_act(uint rows, uint cols, __global float* Y, uint y_off, uint ld, __global const float* bias,
                       uint bias_off, uint act) {
  const uint j = (uint)get_global_id(0);
  const uint i = (uint)get_global_id(1);
  if (i >= rows || j >= cols) return;
  __global float* p = Y + y_off + i * ld + j;
  *p = apply_act(*p + bias[bias_off + j], act);
}
