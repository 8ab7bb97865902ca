// Sums of float arrays. Each work-group reduces in local memory, then adds its partial sum atomically,
// so one launch gives the total with n/local atomics instead of n. Needs atomics.cl before it.
// Non-finite inputs are skipped and counted (docs/design.md §7: drop and count non-finite samples).
__kernel void sum_f32(__global const float* x, unsigned int n, __global float* total,
                      volatile __global unsigned int* non_finite, __local float* scratch) {
  const size_t gid = get_global_id(0);
  float v = 0.0f;
  if (gid < n) {
    v = x[gid];
    if (!isfinite(v)) {
      atomic_inc(non_finite);
      v = 0.0f;
    }
  }
  group_add_f32(total, v, scratch);  // the group size is a power of two (the host launches with one)
}

__kernel void fill_f32(__global float* x, unsigned int n, float value) {
  const size_t gid = get_global_id(0);
  if (gid < n) x[gid] = value;
}
