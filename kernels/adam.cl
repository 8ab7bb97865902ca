// Adam with decoupled weight decay (AdamW: p -= lr·wd·p, not folded into the moments) over one parameter buffer,
// so a whole network is one launch. The step's gradient is consumed and zeroed here, which saves the separate
// clearing pass before the next backward. Non-finite gradient values are dropped (that element is not updated
// this step) and counted (docs/design.md §7).
// c1 = 1 / (1 − β1^t), c2 = 1 / (1 − β2^t): bias corrections, computed in double on the host.
inline void adam_apply(uint i, float gi, __global float* p, __global float* m, __global float* v, float lr, float b1,
                       float b2, float eps, float wd, float c1, float c2, volatile __global uint* non_finite) {
  if (!isfinite(gi)) {
    atomic_inc(non_finite);
    return;
  }
  const float mi = b1 * m[i] + (1.0f - b1) * gi;
  const float vi = b2 * v[i] + (1.0f - b2) * gi * gi;
  m[i] = mi;
  v[i] = vi;
  p[i] -= lr * (mi * c1 / (sqrt(vi * c2) + eps) + wd * p[i]);
}

inline void adam_update(uint i, __global float* p, __global float* g, __global float* m, __global float* v, float lr,
                        float b1, float b2, float eps, float wd, float c1, float c2,
                        volatile __global uint* non_finite) {
  const float gi = g[i];
  g[i] = 0.0f;
  adam_apply(i, gi, p, m, v, lr, b1, b2, eps, wd, c1, c2, non_finite);
}

__kernel void adam_step(uint n, __global float* p, __global float* g, __global float* m, __global float* v, float lr,
                        float b1, float b2, float eps, float wd, float c1, float c2,
                        volatile __global uint* non_finite) {
  const uint i = (uint)get_global_id(0);
  if (i < n) adam_update(i, p, g, m, v, lr, b1, b2, eps, wd, c1, c2, non_finite);
}

// Lazy Adam over a table of `entries` rows of `features` floats: only rows whose `touched` flag the backward pass
// set are updated (and their flag cleared). Untouched rows keep their moments and values, as PyTorch's SparseAdam
// does; the bias corrections use the global step. This turns the per-step cost from the whole table into the
// entries a batch reached (docs/design.md §6), at the price of no momentum drift on untouched entries.
__kernel void adam_step_sparse(uint entries, uint features, __global uchar* touched, __global float* p,
                               __global float* g, __global float* m, __global float* v, float lr, float b1, float b2,
                               float eps, float wd, float c1, float c2, volatile __global uint* non_finite) {
  const uint e = (uint)get_global_id(0);
  if (e >= entries || !touched[e]) return;
  touched[e] = 0;
  for (uint f = 0; f < features; ++f)
    adam_update(e * features + f, p, g, m, v, lr, b1, b2, eps, wd, c1, c2, non_finite);
}

// The same lazy update for a table whose gradient is int64 fixed point in units of 2^-40 (kernels/hashgrid.cl).
__kernel void adam_step_sparse_fixed(uint entries, uint features, __global uchar* touched, __global float* p,
                                     __global long* g, __global float* m, __global float* v, float lr, float b1,
                                     float b2, float eps, float wd, float c1, float c2,
                                     volatile __global uint* non_finite) {
  const uint e = (uint)get_global_id(0);
  if (e >= entries || !touched[e]) return;
  touched[e] = 0;
  for (uint f = 0; f < features; ++f) {
    const uint i = e * features + f;
    const float gi = convert_float(g[i]) * 0x1p-40f;
    g[i] = 0;
    adam_apply(i, gi, p, m, v, lr, b1, b2, eps, wd, c1, c2, non_finite);
  }
}

// a[i] = d·a[i] + (1 − d)·p[i]: an exponential moving average of parameters (nn::Network::update_average).
__kernel void average_f32(uint n, float d, __global const float* p, __global float* a) {
  const uint i = (uint)get_global_id(0);
  if (i < n) a[i] = d * a[i] + (1.0f - d) * p[i];
}
