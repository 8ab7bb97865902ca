// Register-blocked GEMM without local memory: C = act(alpha · op(A) · B + beta · C + bias).
//
// Each work-item owns a TM × (VW·NV) tile of C and keeps it in vector registers for the whole k loop; B rows are
// loaded as VW-wide vectors and every A element is broadcast into TM·NV fused multiply-adds. On PoCL's CPU device
// a tile that fills about half the vector registers (AVX-512: 8 rows × 2 float16; AVX2: 6 rows × float16) runs
// several times faster than CLBlast's kernels, which are untuned there (docs/design.md §6; figures in
// docs/results/benchmarks.md). The host times candidate tiles per device (nn/gemm.hpp) and passes the winner as
// TM, VW, NV; GPUs get smaller tiles.
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

// One element of C from its accumulated product, the epilogue of every kernel here and in gemm_tiled.cl and
// gemm_tf32.cl: *c = act(alpha · acc + beta · *c + bias), `bias` pointing at the element's column.
inline void store_c(__global float* c, float acc, float alpha, float beta, __global const float* bias, uint use_bias,
                    uint act) {
  float r = alpha * acc;
  // beta == 0 must not read C: it may hold garbage (or NaN) that 0·C would propagate.
  if (beta != 0.0f) r += beta * *c;
  if (use_bias) r += *bias;
  *c = apply_act(r, act);
}

// The part of C and of the reduction that a work-group of the tiled kernels (gemm_tiled.cl, gemm_tf32.cl) owns: group
// row gm is tile row gm mod ⌈M/bm⌉ of k-slice gm div ⌈M/bm⌉ (split-K, each slice written to C + slice·c_slice), group
// column the tile column. A slice past K is empty, [K, K): such groups run an empty loop rather than return early, so
// every work-item reaches every barrier.
typedef struct {
  uint m0, n0, kb, ke, slice;
} GemmTile;

inline GemmTile gemm_tile(uint M, uint K, uint k_slice, uint bm, uint bn) {
  GemmTile t;
  const uint tiles_m = (M + bm - 1) / bm;
  const uint gm = (uint)get_group_id(1);
  t.slice = gm / tiles_m;
  t.m0 = (gm - t.slice * tiles_m) * bm;
  t.n0 = (uint)get_group_id(0) * bn;
  t.kb = min(K, t.slice * k_slice);
  t.ke = min(K, t.kb + k_slice);
  return t;
}

__kernel void gemm_own(uint M, uint N, uint K, float alpha, __global const float* A, uint a_off, uint a_rs, uint a_cs,
                       __global const float* B, uint b_off, uint ldb, float beta, __global float* C, uint c_off,
                       uint ldc, uint k_slice, uint c_slice, __global const float* bias, uint bias_off, uint use_bias,
                       uint act, uint b_padded) {
  const uint tiles_m = (M + TM - 1) / TM;
  const uint n0 = (uint)get_global_id(0) * TN;
  const uint gm = (uint)get_global_id(1);
  const uint slice = gm / tiles_m;
  const uint m0 = (gm - slice * tiles_m) * TM;
  const uint kb = slice * k_slice;
  if (n0 >= N || m0 >= M || kb >= K) return;  // padding work-items; no barriers in this kernel
  const uint ke = min(K, kb + k_slice);
  __global float* Cs = C + c_off + slice * c_slice;

  const uint mm = min((uint)TM, M - m0);
  const uint nn = min((uint)TN, N - n0);
  // Vector path: full column tiles, or partial ones when B has TN floats of padding after its last row
  // (b_padded, the host's transposed copies), whose extra lanes are computed and dropped. Rows past M re-read
  // row M-1 (always in bounds) and are not stored, so a partial row tile costs no scalar code.
  if (nn == TN || b_padded) {
    floatV acc[TM][NV];
#pragma unroll
    for (uint i = 0; i < TM; ++i)
#pragma unroll
      for (uint v = 0; v < NV; ++v) acc[i][v] = (floatV)(0.0f);
    uint roff[TM];
#pragma unroll
    for (uint i = 0; i < TM; ++i) roff[i] = min(i, mm - 1) * a_rs;
    __global const float* ap = A + a_off + m0 * a_rs + kb * a_cs;
    __global const float* bp = B + b_off + kb * ldb + n0;
    for (uint k = kb; k < ke; ++k) {
      floatV b[NV];
#pragma unroll
      for (uint v = 0; v < NV; ++v) b[v] = vloadV(v, bp);
#pragma unroll
      for (uint i = 0; i < TM; ++i) {
        const floatV a = (floatV)(ap[roff[i]]);
#pragma unroll
        for (uint v = 0; v < NV; ++v) acc[i][v] = fma(a, b[v], acc[i][v]);
      }
      ap += a_cs;
      bp += ldb;
    }
#pragma unroll
    for (uint i = 0; i < TM; ++i) {
      // Rows past the matrix are skipped, not broken out of: a loop with a break cannot be fully unrolled, and acc
      // must stay in registers (indexed only by unrolled constants).
      if (i < mm) {
        __global float* cp = Cs + (m0 + i) * ldc + n0;
        if (nn == TN) {
#pragma unroll
          for (uint v = 0; v < NV; ++v) {
            floatV r = alpha * acc[i][v];
            // beta == 0 must not read C: it may hold garbage (or NaN) that 0·C would propagate.
            if (beta != 0.0f) r += beta * vloadV(v, cp);
            if (use_bias) r += vloadV(v, bias + bias_off + n0);
            vstoreV(apply_act_v(r, act), v, cp);
          }
        } else {
          float t[TN];
#pragma unroll
          for (uint v = 0; v < NV; ++v) vstoreV(acc[i][v], v, t);
          for (uint j = 0; j < nn; ++j) store_c(cp + j, t[j], alpha, beta, bias + bias_off + n0 + j, use_bias, act);
        }
      }
    }
  } else {
    // Partial column tile of an unpadded B: scalar, the column loop bounded at run time.
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
      for (uint j = 0; j < nn; ++j)
        store_c(Cs + (m0 + i) * ldc + n0 + j, acc[i * TN + j], alpha, beta, bias + bias_off + n0 + j, use_bias, act);
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

// Products with at most 4 output columns (the radiance output layer), where a TN-wide register tile would waste
// 90 % of its work. Both kernels vectorise along the long dimension instead.
//
// gemm_narrow_nn: C[m × n] = act(alpha · A·B + beta · C + bias), A row-major (lda), Bt = Bᵀ packed as [4 × K]
// with rows ≥ n zero. One work-item per row of C: 4 float16 dot-product accumulators along k.
__kernel void gemm_narrow_nn(uint M, uint N, uint K, float alpha, __global const float* A, uint a_off, uint lda,
                             __global const float* Bt, float beta, __global float* C, uint c_off, uint ldc,
                             __global const float* bias, uint bias_off, uint use_bias, uint act) {
  const uint i = (uint)get_global_id(0);
  if (i >= M) return;
  __global const float* a = A + a_off + i * lda;
  float16 acc0 = (float16)(0.0f), acc1 = acc0, acc2 = acc0, acc3 = acc0;
  uint k = 0;
  for (; k + 16 <= K; k += 16) {
    const float16 av = vload16(0, a + k);
    acc0 = fma(av, vload16(0, Bt + k), acc0);
    acc1 = fma(av, vload16(0, Bt + K + k), acc1);
    acc2 = fma(av, vload16(0, Bt + 2 * K + k), acc2);
    acc3 = fma(av, vload16(0, Bt + 3 * K + k), acc3);
  }
  float s[4];
  s[0] = acc0.s0 + acc0.s1 + acc0.s2 + acc0.s3 + acc0.s4 + acc0.s5 + acc0.s6 + acc0.s7 + acc0.s8 + acc0.s9 + acc0.sa +
         acc0.sb + acc0.sc + acc0.sd + acc0.se + acc0.sf;
  s[1] = acc1.s0 + acc1.s1 + acc1.s2 + acc1.s3 + acc1.s4 + acc1.s5 + acc1.s6 + acc1.s7 + acc1.s8 + acc1.s9 + acc1.sa +
         acc1.sb + acc1.sc + acc1.sd + acc1.se + acc1.sf;
  s[2] = acc2.s0 + acc2.s1 + acc2.s2 + acc2.s3 + acc2.s4 + acc2.s5 + acc2.s6 + acc2.s7 + acc2.s8 + acc2.s9 + acc2.sa +
         acc2.sb + acc2.sc + acc2.sd + acc2.se + acc2.sf;
  s[3] = acc3.s0 + acc3.s1 + acc3.s2 + acc3.s3 + acc3.s4 + acc3.s5 + acc3.s6 + acc3.s7 + acc3.s8 + acc3.s9 + acc3.sa +
         acc3.sb + acc3.sc + acc3.sd + acc3.se + acc3.sf;
  for (; k < K; ++k) {
    const float av = a[k];
    for (uint j = 0; j < 4; ++j) s[j] = fma(av, Bt[j * K + k], s[j]);
  }
  for (uint j = 0; j < N; ++j) store_c(C + c_off + i * ldc + j, s[j], alpha, beta, bias + bias_off + j, use_bias, act);
}

// gemm_narrow_tn: partial products P[s][i][j] = Σ_{k in slice s} A[k, i] · B[k, j] for j < n ≤ 4, A row-major
// [K × M] (lda), B row-major [K × n] (ldb). Work-item (i-block of 16, slice): 4 float16 accumulators along i.
// The host sums the slices in order with gemm_reduce_slices (packed as [slices × M × N]).
__kernel void gemm_narrow_tn(uint M, uint N, uint K, __global const float* A, uint a_off, uint lda,
                             __global const float* B, uint b_off, uint ldb, uint k_slice, __global float* P) {
  const uint i0 = (uint)get_global_id(0) * 16;
  const uint slice = (uint)get_global_id(1);
  const uint kb = slice * k_slice;
  if (i0 >= M || kb >= K) return;
  const uint ke = min(K, kb + k_slice);
  float16 acc0 = (float16)(0.0f), acc1 = acc0, acc2 = acc0, acc3 = acc0;
  if (i0 + 16 <= M) {
    for (uint k = kb; k < ke; ++k) {
      const float16 av = vload16(0, A + a_off + k * lda + i0);
      __global const float* b = B + b_off + k * ldb;
      acc0 = fma(av, (float16)(b[0]), acc0);
      if (N > 1) acc1 = fma(av, (float16)(b[1]), acc1);
      if (N > 2) acc2 = fma(av, (float16)(b[2]), acc2);
      if (N > 3) acc3 = fma(av, (float16)(b[3]), acc3);
    }
  } else {
    // Tail block: rows past M read as zero.
    for (uint k = kb; k < ke; ++k) {
      float t[16];
      for (uint r = 0; r < 16; ++r) t[r] = i0 + r < M ? A[a_off + k * lda + i0 + r] : 0.0f;
      const float16 av = vload16(0, t);
      __global const float* b = B + b_off + k * ldb;
      acc0 = fma(av, (float16)(b[0]), acc0);
      if (N > 1) acc1 = fma(av, (float16)(b[1]), acc1);
      if (N > 2) acc2 = fma(av, (float16)(b[2]), acc2);
      if (N > 3) acc3 = fma(av, (float16)(b[3]), acc3);
    }
  }
  float o[4][16];
  vstore16(acc0, 0, o[0]);
  vstore16(acc1, 0, o[1]);
  vstore16(acc2, 0, o[2]);
  vstore16(acc3, 0, o[3]);
  __global float* p = P + slice * M * N;
  for (uint r = 0; r < 16 && i0 + r < M; ++r)
    for (uint j = 0; j < N; ++j) p[(i0 + r) * N + j] = o[j][r];
}

// C = 0 over rows × cols (ld). CLBlast computes alpha·AB + beta·C even for beta = 0, so a C that holds garbage
// (a fresh buffer may hold NaN bit patterns) must be cleared first.
__kernel void zero_matrix(uint rows, uint cols, __global float* C, uint c_off, uint ld) {
  const uint j = (uint)get_global_id(0);
  const uint i = (uint)get_global_id(1);
  if (i < rows && j < cols) C[c_off + i * ld + j] = 0.0f;
}
