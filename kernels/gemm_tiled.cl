// Local-memory tiled GEMM, the classic GPU shape: C = act(alpha · op(A) · B + beta · C + bias).
//
// gemm.cl's register-blocked kernel reads A and B straight from global memory, which a CPU's caches forgive and a
// GPU does not: there every work-item would fetch its own panels. Here a work-group of (BN/WN) × (BM/WM)
// work-items computes a BM × BN tile of C; per step of BK along k the group stages the A and B panels in __local
// memory once (each element read from global memory by one work-item, coalesced), synchronises, and every
// work-item accumulates its WM × WN share of the tile in registers from local memory. A work-item's rows and
// columns are strided by the group's extent (row ly + i·LY, column lx + j·LX), so neighbouring work-items read
// neighbouring local words and write neighbouring words of C.
//
// Same arguments and addressing as gemm_own (op(A) through strides, B row-major with unit column stride, split-K
// slices written to C + s·c_slice), so the host's transposes, k-blocking and slice reduction serve both kernels.
// Every edge (rows, columns, the k tail) is bounds-checked with zero fill; b_padded is not needed and ignored.
// Sizes are -D defines (the host's candidates stay within NVIDIA's 48 KiB of local memory and 1024 work-items);
// the group is fixed at compile time, so the launch must be (BN/WN) × (BM/WM).
//
// VEC 4 (WM and WN multiples of 4): a work-item's rows and columns come in runs of 4 (run c of rows at
// c·4·LY + 4·ly), so each k step reads its A and B values from local memory as WM/4 + WN/4 float4 loads instead of
// WM + WN scalar ones — the GPU's shared-memory bandwidth, not its FMA rate, limits the scalar form at 8 × 8
// (16 loads for 64 FMAs). The A panel's rows are padded by 4 words to keep every run 16-byte aligned.
#ifndef BM
#define BM 64
#endif
#ifndef BN
#define BN 64
#endif
#ifndef BK
#define BK 16
#endif
#ifndef WM
#define WM 4
#endif
#ifndef WN
#define WN 4
#endif
#ifndef VEC
#define VEC 1
#endif
#define LX (BN / WN)
#define LY (BM / WM)
#define THREADS (LX * LY)
#if VEC == 4
// Row i (column j) of a work-item's share of the tile: runs of 4 consecutive rows, LY·4 apart.
#define ROW_OF(i) (((i) / 4) * (LY * 4) + ly * 4 + (i) % 4)
#define COL_OF(j) (((j) / 4) * (LX * 4) + lx * 4 + (j) % 4)
// Four words of padding per A row keep the float4 runs aligned; with BK = 8 the panel's writes (k fastest across
// work-items) still fall into distinct banks (k·4 + row spans 32 words).
#define AS_LD (BM + 4)
#else
#define ROW_OF(i) (ly + (i)*LY)
#define COL_OF(j) (lx + (j)*LX)
// One word of padding per A row: the panel is written with k varying fastest across work-items (a row-major A),
// and without it those writes, BM words apart, would all fall into one local memory bank.
#define AS_LD (BM + 1)
#endif

__kernel __attribute__((reqd_work_group_size(LX, LY, 1))) void gemm_tiled(
    uint M, uint N, uint K, float alpha, __global const float* A, uint a_off, uint a_rs, uint a_cs,
    __global const float* B, uint b_off, uint ldb, float beta, __global float* C, uint c_off, uint ldc, uint k_slice,
    uint c_slice, __global const float* bias, uint bias_off, uint use_bias, uint act, uint b_padded) {
  (void)b_padded;
#if VEC == 4
  // float4 arrays for aligned vector reads; the panels are written through float views.
  __local float4 As4[BK * AS_LD / 4];
  __local float4 Bs4[BK * BN / 4];
  __local float* As = (__local float*)As4;
  __local float* Bs = (__local float*)Bs4;
#else
  __local float As[BK * AS_LD];  // As[k][m]: k-major, so a work-item's WM rows at one k are one local row
  __local float Bs[BK * BN];     // Bs[k][n]
#endif
  const uint lx = (uint)get_local_id(0), ly = (uint)get_local_id(1);
  const uint lid = ly * LX + lx;
  const GemmTile tile = gemm_tile(M, K, k_slice, BM, BN);
  const uint m0 = tile.m0, n0 = tile.n0, kb = tile.kb, ke = tile.ke;
  __global float* Cs = C + c_off + tile.slice * c_slice;

  float acc[WM][WN];
#pragma unroll
  for (uint i = 0; i < WM; ++i)
#pragma unroll
    for (uint j = 0; j < WN; ++j) acc[i][j] = 0.0f;

  for (uint k0 = kb; k0 < ke; k0 += BK) {
    // Stage the A panel. Consecutive work-items walk along k when A's k stride is 1 (op(A) = A) and along m
    // otherwise (op(A) = Aᵀ), so their global reads are contiguous either way.
    for (uint e = lid; e < BM * BK; e += THREADS) {
      const uint r = a_cs == 1 ? e / BK : e % BM;
      const uint kk = a_cs == 1 ? e % BK : e / BM;
      const uint row = m0 + r, k = k0 + kk;
      As[kk * AS_LD + r] = row < M && k < ke ? A[a_off + row * a_rs + k * a_cs] : 0.0f;
    }
    for (uint e = lid; e < BN * BK; e += THREADS) {
      const uint kk = e / BN, col = n0 + e % BN, k = k0 + kk;
      Bs[e] = col < N && k < ke ? B[b_off + k * ldb + col] : 0.0f;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
#pragma unroll
    for (uint kk = 0; kk < BK; ++kk) {
      float a[WM], b[WN];
#if VEC == 4
#pragma unroll
      for (uint c = 0; c < WM / 4; ++c) vstore4(As4[(kk * AS_LD + c * LY * 4) / 4 + ly], c, a);
#pragma unroll
      for (uint c = 0; c < WN / 4; ++c) vstore4(Bs4[(kk * BN + c * LX * 4) / 4 + lx], c, b);
#else
#pragma unroll
      for (uint i = 0; i < WM; ++i) a[i] = As[kk * AS_LD + ROW_OF(i)];
#pragma unroll
      for (uint j = 0; j < WN; ++j) b[j] = Bs[kk * BN + COL_OF(j)];
#endif
#pragma unroll
      for (uint i = 0; i < WM; ++i)
#pragma unroll
        for (uint j = 0; j < WN; ++j) acc[i][j] = fma(a[i], b[j], acc[i][j]);
    }
    // The next iteration overwrites the panels other work-items may still be reading.
    barrier(CLK_LOCAL_MEM_FENCE);
  }

#pragma unroll
  for (uint i = 0; i < WM; ++i) {
    const uint row = m0 + ROW_OF(i);
#pragma unroll
    for (uint j = 0; j < WN; ++j) {
      const uint col = n0 + COL_OF(j);
      if (row < M && col < N)
        store_c(Cs + row * ldc + col, acc[i][j], alpha, beta, bias + bias_off + col, use_bias, act);
    }
  }
}
