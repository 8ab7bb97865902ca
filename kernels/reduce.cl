// Sums of float arrays. Each work-group reduces in local memory, then adds its partial sum atomically,
// so one launch gives the total with n/local atomics instead of n. Needs atomics.cl before it.
// Non-finite inputs are skipped and counted (docs/design.md §7: drop and count non-finite samples).
__kernel void sum_f32(__global const float* x, unsigned int n, __global float* total,
                      volatile __global unsigned int* non_finite, __local float* scratch) {
  const size_t gid = get_global_id(0);
  const size_t lid = get_local_id(0);
  float v = 0.0f;
  if (gid < n) {
    v = x[gid];
    if (!isfinite(v)) {
      atomic_inc(non_finite);
      v = 0.0f;
    }
  }
  scratch[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  // Tree reduction; the group size is a power of two (the host launches with one).
  for (size_t s = get_local_size(0) / 2; s > 0; s >>= 1) {
    if (lid < s) scratch[lid] += scratch[lid + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) atomic_add_f32(total, scratch[0]);
}

__kernel void fill_f32(__global float* x, unsigned int n, float value) {
  const size_t gid = get_global_id(0);
  if (gid < n) x[gid] = value;
}
