// The device's measured FMA throughput, the ceiling that GEMM figures are reported against (DESIGN.md §6).
// Eight independent float16 chains per work-item hide the FMA latency; the result is stored so the chains are not
// optimised away. Each iteration is 8 chains × 16 lanes × 2 flops.
__kernel void fma_peak(uint iterations, float a, float b, __global float* out) {
  float16 x0 = (float16)(get_global_id(0)), x1 = x0 + 1.0f, x2 = x0 + 2.0f, x3 = x0 + 3.0f;
  float16 x4 = x0 + 4.0f, x5 = x0 + 5.0f, x6 = x0 + 6.0f, x7 = x0 + 7.0f;
  const float16 va = (float16)(a), vb = (float16)(b);
  for (uint i = 0; i < iterations; ++i) {
    x0 = fma(x0, va, vb);
    x1 = fma(x1, va, vb);
    x2 = fma(x2, va, vb);
    x3 = fma(x3, va, vb);
    x4 = fma(x4, va, vb);
    x5 = fma(x5, va, vb);
    x6 = fma(x6, va, vb);
    x7 = fma(x7, va, vb);
  }
  const float16 s = x0 + x1 + x2 + x3 + x4 + x5 + x6 + x7;
  out[get_global_id(0)] =
      s.s0 + s.s1 + s.s2 + s.s3 + s.s4 + s.s5 + s.s6 + s.s7 + s.s8 + s.s9 + s.sa + s.sb + s.sc + s.sd + s.se + s.sf;
}
