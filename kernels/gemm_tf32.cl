// TF32 tensor-core GEMM, NVIDIA only (sm_80 and later: inline PTX `mma.sync ... tf32`), same contract and arguments
// as gemm_tiled.cl: C = act(alpha · op(A) · B + beta · C + bias), split-K slices, bounds-checked edges.
//
// Why: the FP32 kernels run the N-Module's products on the FMA units, at most ~64 TFLOP/s on an H100/H200 and a third
// of that in practice; the tensor cores take TF32 (each factor rounded to 10 mantissa bits, products summed in FP32)
// at several times that rate. The host builds this program only for a device whose compute capability (read through
// cl_nv_device_attribute_query) is 8.0 or newer, and the probe picks it only where it is faster than every FP32
// candidate and its product stays within the TF32 bound of an FP32 one (nn/gemm.cpp); tests check it against the
// double twin with that bound. The tolerated error is the rounding of each factor to TF32: |C − C_exact| ≤
// 2^-9 · |alpha| · Σ_k |A_ik · B_kj| (twice the unit roundoff 2^-11 per factor, with room for the FP32 sum).
//
// Shape: a work-group of LY warps (dimension 0 is a warp's 32 lanes) computes a BM × BN tile of C; the warps form a
// WARPS_M × (LY / WARPS_M) grid, each owning a WTM × WTN sub-tile as MT × NT fragments of m16n8k8 (MT·NT·4
// accumulators a lane: WM × WN in the host's GemmBlock). Per BK step the group stages the A panel (m-major, k
// contiguous) and the B panel (k-major) in __local memory, converted to TF32 once there; the next panel's global
// reads are issued into registers before the current one's MMAs, so they are in flight while the tensor cores work.
// Strides are padded so that a warp's fragment reads hit 32 distinct banks (A: row·(BK+4) + k, B: k·(BN+8) + n).
// STAGES 2 double-buffers the panels: the next panel is stored into the other buffer while this one's MMAs run, so a
// panel costs one barrier instead of two (the H100 run: two barriers per 16-deep panel left the tensor cores idle).
//
// TF32_EMULATE (CPU lanes only: the host sets it where the device runs no PTX) replaces the two PTX instructions by
// their definitions: the rounding in integer arithmetic and mma.sync's exchange of fragments between a warp's lanes
// through local memory. So PoCL and Intel's runtime test this file's tiling, fragment layout and buffering against
// the double twin; only the two instructions themselves are left to the GPU run.
#ifndef BM
#define BM 128
#endif
#ifndef BN
#define BN 128
#endif
#ifndef BK
#define BK 32
#endif
#ifndef WM
#define WM 16
#endif
#ifndef WN
#define WN 4
#endif
#define LX (BN / WN)
#define LY (BM / WM)
#define THREADS (LX * LY)
#if LX != 32
#error "gemm_tf32: BN / WN must be 32 (dimension 0 of the group is one warp)"
#endif
#define WARPS_M 2
#define WARPS_N (LY / WARPS_M)
#define WTM (BM / WARPS_M)
#define WTN (BN / WARPS_N)
#define MT (WTM / 16)
#define NT (WTN / 8)
#if MT * NT * 4 != WM * WN || BK % 8 != 0
#error "gemm_tf32: a lane's accumulators must be WM x WN and BK a multiple of 8"
#endif
#ifndef STAGES
#define STAGES 1
#endif
#if STAGES != 1 && STAGES != 2
#error "gemm_tf32: STAGES is 1 or 2"
#endif
#define A_LD (BK + 4)
#define B_LD (BN + 8)
#define A_LOADS (BM * BK / THREADS)
#define B_LOADS (BN * BK / THREADS)

#ifdef TF32_EMULATE
// cvt.rna.tf32.f32: to nearest, ties away from zero (adding half an ulp of TF32 to the magnitude), Inf and NaN kept.
inline uint to_tf32(float x) {
  const uint u = as_uint(x);
  return (u & 0x7f800000u) == 0x7f800000u ? u : (u + 0x1000u) & 0xffffe000u;
}

// mma.sync for one warp: every lane publishes its a0..a3, b0, b1 in `f` (32 × 6 words), then forms its four sums
// from the lanes that hold the rows and columns it needs (layout as below). Every work-item of the group calls it
// the same number of times, so the barriers are uniform.
inline void mma_tf32(float* c, const uint* a, const uint* b, __local uint* f, uint lane) {
  barrier(CLK_LOCAL_MEM_FENCE);  // the previous exchange has been read
  for (uint q = 0; q < 4; ++q) f[lane * 6 + q] = a[q];
  f[lane * 6 + 4] = b[0];
  f[lane * 6 + 5] = b[1];
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint group = lane >> 2, t = lane & 3;
  for (uint q = 0; q < 4; ++q) {
    const uint r = group + (q / 2) * 8, n = 2 * t + q % 2;
    float s = c[q];
    for (uint k = 0; k < 8;
         ++k)  // A[r][k] is a[(r / 8) + 2 (k / 4)] of lane 4 (r % 8) + k % 4; B[k][n] b[k / 4] of 4n + k % 4
      s += as_float(f[(4 * (r % 8) + k % 4) * 6 + r / 8 + 2 * (k / 4)]) * as_float(f[(4 * n + k % 4) * 6 + 4 + k / 4]);
    c[q] = s;
  }
}
#define MMA(c, a, b) mma_tf32(c, a, b, frags + warp * 32 * 6, lane)
// Unrolled around the exchange's barriers, the kernel takes PoCL many minutes to compile.
#define UNROLL
#else
// clang spells GNU inline assembly __asm__ in OpenCL C; NVIDIA's own front end takes asm.
#ifdef __clang__
#define PTX __asm__
#else
#define PTX asm
#endif

// Round to nearest (ties away) to TF32: the low 13 mantissa bits cleared.
inline uint to_tf32(float x) {
  uint r;
  PTX("cvt.rna.tf32.f32 %0, %1;" : "=r"(r) : "f"(x));
  return r;
}

// c += a · b for one 16 × 8 × 8 fragment (the PTX ISA's layout: lane = 4·group + t; a0/a1 rows group and group + 8
// at k = t, a2/a3 the same at k = t + 4; b0/b1 column group at k = t, t + 4; c0/c1 row group at columns 2t, 2t + 1,
// c2/c3 row group + 8).
inline void mma_tf32(float* c, const uint* a, const uint* b) {
  PTX volatile(
      "mma.sync.aligned.m16n8k8.row.col.f32.tf32.tf32.f32 {%0,%1,%2,%3}, {%4,%5,%6,%7}, {%8,%9}, "
      "{%0,%1,%2,%3};"
      : "+f"(c[0]), "+f"(c[1]), "+f"(c[2]), "+f"(c[3])
      : "r"(a[0]), "r"(a[1]), "r"(a[2]), "r"(a[3]), "r"(b[0]), "r"(b[1]));
}
#define MMA(c, a, b) mma_tf32(c, a, b)
#define UNROLL _Pragma("unroll")
#endif

__kernel __attribute__((reqd_work_group_size(LX, LY, 1))) void gemm_tiled(
    uint M, uint N, uint K, float alpha, __global const float* A, uint a_off, uint a_rs, uint a_cs,
    __global const float* B, uint b_off, uint ldb, float beta, __global float* C, uint c_off, uint ldc, uint k_slice,
    uint c_slice, __global const float* bias, uint bias_off, uint use_bias, uint act, uint b_padded) {
  (void)b_padded;
  __local uint As[STAGES][BM * A_LD];  // As[m][k], TF32 bit patterns
  __local uint Bs[STAGES][BK * B_LD];  // Bs[k][n]
#ifdef TF32_EMULATE
  __local uint frags[LY * 32 * 6];
#endif
  const uint lane = (uint)get_local_id(0), warp = (uint)get_local_id(1);
  const uint lid = warp * 32 + lane;
  const uint group = lane >> 2, t = lane & 3;
  const uint wm0 = (warp % WARPS_M) * WTM, wn0 = (warp / WARPS_M) * WTN;
  const GemmTile tile = gemm_tile(M, K, k_slice, BM, BN);
  const uint m0 = tile.m0, n0 = tile.n0, kb = tile.kb, ke = tile.ke;
  __global float* Cs = C + c_off + tile.slice * c_slice;
  // Consecutive work-items walk along k when A's k stride is 1 (op(A) = A) and along m otherwise, so their global
  // reads are contiguous either way; B is always read along n.
  const bool a_k_fast = a_cs == 1;

  float acc[MT][NT][4];
#pragma unroll
  for (uint i = 0; i < MT; ++i)
#pragma unroll
    for (uint j = 0; j < NT; ++j)
#pragma unroll
      for (uint q = 0; q < 4; ++q) acc[i][j][q] = 0.0f;

  float ra[A_LOADS], rb[B_LOADS];
#define LOAD_PANELS(k0)                                                         \
  UNROLL for (uint i = 0; i < A_LOADS; ++i) {                                   \
    const uint e = lid + i * THREADS;                                           \
    const uint r = a_k_fast ? e / BK : e % BM, kk = a_k_fast ? e % BK : e / BM; \
    const uint row = m0 + r, k = (k0) + kk;                                     \
    ra[i] = row < M && k < ke ? A[a_off + row * a_rs + k * a_cs] : 0.0f;        \
  }                                                                             \
  UNROLL for (uint i = 0; i < B_LOADS; ++i) {                                   \
    const uint e = lid + i * THREADS;                                           \
    const uint col = n0 + e % BN, k = (k0) + e / BN;                            \
    rb[i] = col < N && k < ke ? B[b_off + k * ldb + col] : 0.0f;                \
  }

#define STORE_PANELS(s)                                                         \
  UNROLL for (uint i = 0; i < A_LOADS; ++i) {                                   \
    const uint e = lid + i * THREADS;                                           \
    const uint r = a_k_fast ? e / BK : e % BM, kk = a_k_fast ? e % BK : e / BM; \
    As[s][r * A_LD + kk] = to_tf32(ra[i]);                                      \
  }                                                                             \
  UNROLL for (uint i = 0; i < B_LOADS; ++i) {                                   \
    const uint e = lid + i * THREADS;                                           \
    Bs[s][(e / BN) * B_LD + e % BN] = to_tf32(rb[i]);                           \
  }
#define MMA_PANEL(s)                                                                                      \
  UNROLL for (uint ks = 0; ks < BK; ks += 8) {                                                            \
    uint a[MT][4], b[NT][2];                                                                              \
    UNROLL for (uint i = 0; i < MT; ++i) {                                                                \
      const uint r = wm0 + i * 16 + group;                                                                \
      a[i][0] = As[s][r * A_LD + ks + t];                                                                 \
      a[i][1] = As[s][(r + 8) * A_LD + ks + t];                                                           \
      a[i][2] = As[s][r * A_LD + ks + t + 4];                                                             \
      a[i][3] = As[s][(r + 8) * A_LD + ks + t + 4];                                                       \
    }                                                                                                     \
    UNROLL for (uint j = 0; j < NT; ++j) {                                                                \
      const uint c = wn0 + j * 8 + group;                                                                 \
      b[j][0] = Bs[s][(ks + t) * B_LD + c];                                                               \
      b[j][1] = Bs[s][(ks + t + 4) * B_LD + c];                                                           \
    }                                                                                                     \
    UNROLL for (uint i = 0; i < MT; ++i) UNROLL for (uint j = 0; j < NT; ++j) MMA(acc[i][j], a[i], b[j]); \
  }

  if (kb < ke) {
    LOAD_PANELS(kb)
  }
#if STAGES == 1
  for (uint k0 = kb; k0 < ke; k0 += BK) {
    STORE_PANELS(0)
    barrier(CLK_LOCAL_MEM_FENCE);
    if (k0 + BK < ke) {
      LOAD_PANELS(k0 + BK)
    }
    MMA_PANEL(0)
    // The next iteration overwrites the panels other warps may still be reading.
    barrier(CLK_LOCAL_MEM_FENCE);
  }
#else
  if (kb < ke) {
    STORE_PANELS(0)
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  uint s = 0;
  for (uint k0 = kb; k0 < ke; k0 += BK, s ^= 1u) {
    const bool next = k0 + BK < ke;
    if (next) {
      LOAD_PANELS(k0 + BK)
    }
    MMA_PANEL(s)
    if (next) {
      STORE_PANELS(s ^ 1u)
    }
    // One barrier a panel: the stores above went to the buffer no warp reads in this iteration; the barrier
    // publishes them and ends every read of buffer s before the next iteration stores into it.
    barrier(CLK_LOCAL_MEM_FENCE);
  }
#endif
#undef MMA_PANEL
#undef STORE_PANELS
#undef LOAD_PANELS

#pragma unroll
  for (uint i = 0; i < MT; ++i)
#pragma unroll
    for (uint j = 0; j < NT; ++j)
#pragma unroll
      for (uint q = 0; q < 4; ++q) {
        const uint row = m0 + wm0 + i * 16 + group + (q / 2) * 8;
        const uint col = n0 + wn0 + j * 8 + 2 * t + q % 2;
        if (row < M && col < N)
          store_c(Cs + row * ldc + col, acc[i][j][q], alpha, beta, bias + bias_off + col, use_bias, act);
      }
}
