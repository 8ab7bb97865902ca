// Float atomic add as a compare-and-swap loop on the bits: PoCL 3.1 has no float atomics (docs/design.md §5).
// Sums built with it vary in order between runs, so their tests use tolerances.
inline void atomic_add_f32(volatile __global float* addr, float value) {
  union {
    unsigned int u;
    float f;
  } expected, desired;
  do {
    expected.f = *addr;
    desired.f = expected.f + value;
  } while (atomic_cmpxchg((volatile __global unsigned int*)addr, expected.u, desired.u) != expected.u);
}
