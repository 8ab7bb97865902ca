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

// Adds each work-item's v to *total with one atomic a work-group rather than one a work-item: a CAS loop that every
// work-item of a large launch aims at one address retries quadratically (on an H200 the I-Module's loss sum, 16384
// work-items on one float, took 33 ms of a 42 ms training step; docs/nvidia.md). Every work-item of the group calls
// it (it holds barriers); the group size is a power of two; `scratch` holds one float a work-item.
inline void group_add_f32(volatile __global float* total, float v, __local float* scratch) {
  const size_t lid = get_local_id(0);
  scratch[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (size_t s = get_local_size(0) / 2; s > 0; s >>= 1) {
    if (lid < s) scratch[lid] += scratch[lid + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0 && scratch[0] != 0.0f) atomic_add_f32(total, scratch[0]);
}
