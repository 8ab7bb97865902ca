// Float atomic add as a compare-and-swap loop on the bits: PoCL 3.1 and NVIDIA's OpenCL have no float atomics
// (docs/design.md §5). Sums built with it vary in order between runs, so their tests use tolerances.
// The target is never read with a plain load: a plain read racing another work-item's atomic_cmpxchg is a data
// race in the OpenCL memory model (Oclgrind's race check reports it). The first attempt guesses +0.0 — sums
// accumulate into zeroed buffers, so it often succeeds at once — and every retry uses the value the failed
// atomic_cmpxchg returned, which is an atomic read.
inline void atomic_add_f32(volatile __global float* addr, float value) {
  volatile __global unsigned int* bits = (volatile __global unsigned int*)addr;
  unsigned int expected = 0u;
  for (;;) {
    const unsigned int seen = atomic_cmpxchg(bits, expected, as_uint(as_float(expected) + value));
    if (seen == expected) return;
    expected = seen;
  }
}
