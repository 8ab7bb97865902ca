// The device's measured FMA throughput, the ceiling that GEMM figures are reported against (docs/design.md §6).
// CHAINS independent VW-wide chains per work-item hide the FMA latency; the result is stored so the chains are not
// optimised away. Each iteration is CHAINS × VW lanes × 2 flops. The host builds it for several vector widths and
// keeps the best: a width whose chains do not fit the register file (float16 on AVX2) spills and under-reports.
#ifndef VW
#define VW 16
#endif
#ifndef CHAINS
#define CHAINS 12
#endif
#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#if VW == 1
#define floatV float
#else
#define floatV CAT(float, VW)
#endif

__kernel void fma_peak(uint iterations, float a, float b, __global float* out) {
  floatV x[CHAINS];
#pragma unroll
  for (int c = 0; c < CHAINS; ++c) x[c] = (floatV)(get_global_id(0) + c);
  const floatV va = (floatV)(a), vb = (floatV)(b);
  for (uint i = 0; i < iterations; ++i) {
#pragma unroll
    for (int c = 0; c < CHAINS; ++c) x[c] = fma(x[c], va, vb);
  }
  floatV s = x[0];
#pragma unroll
  for (int c = 1; c < CHAINS; ++c) s += x[c];
#if VW == 1
  out[get_global_id(0)] = s;
#else
  float t[VW];
  CAT(vstore, VW)(s, 0, t);
  float r = 0.0f;
  for (int l = 0; l < VW; ++l) r += t[l];
  out[get_global_id(0)] = r;
#endif
}
