// Multiresolution hash-grid encoding (instant-ngp, Müller et al. 2022). Needs atomics.cl before it.
// Level l has resolution N_l = floor(N_min · b^l) cells per axis, i.e. (N_l + 1)³ vertices. Levels whose vertices
// fit the table ((N_l + 1)³ ≤ T) index densely; finer levels hash a vertex v to (v.x·1 ⊕ v.y·2654435761 ⊕
// v.z·805459861) mod T (T a power of two). Features are trilinearly interpolated from the cell's 8 vertices.
// Per-level info (uint4): x = N_l, y = 1 if dense, z = first entry of the level in the table, w = entries.
// The table is [entries × F] floats; F (features per level) is a -D define.
#ifndef F
#define F 2
#endif

// Gradient accumulation. With FIXED_POINT_GRAD the table gradient is int64 fixed point (2^-40 units) added with
// native 64-bit atomics: integer addition is associative, so the sum, and the whole training step, is the same
// bit for bit whatever the thread schedule, and one atom_add is cheaper than a contended CAS loop. 2^-40 keeps
// ~1e-5 relative precision for contributions down to 1e-7 and sums up to 8e6 in magnitude; out-of-range values
// saturate. Without it (devices lacking cl_khr_int64_base_atomics), float CAS loops: order-dependent last bits.
#ifdef FIXED_POINT_GRAD
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define GRAD_T long
inline void grad_add(volatile __global long* p, float v) { atom_add(p, convert_long_sat_rte(v * 0x1p40f)); }
#else
#define GRAD_T float
inline void grad_add(volatile __global float* p, float v) { atomic_add_f32(p, v); }
#endif

inline uint grid_index(uint3 v, uint4 info) {
  if (info.y) {
    const uint side = info.x + 1;
    return v.x + side * (v.y + side * v.z);
  }
  return (v.x ^ (v.y * 2654435761u) ^ (v.z * 805459861u)) & (info.w - 1);
}

// Cell and fractional position of p ∈ [0, 1]³ (clamped) at resolution res: the point x = 1 belongs to the last cell.
inline void grid_cell(float3 p, uint res, uint3* cell, float3* frac) {
  const float3 pos = clamp(p, 0.0f, 1.0f) * (float)res;
  const float3 c = fmin(floor(pos), (float3)((float)res - 1.0f));
  *cell = convert_uint3(c);
  *frac = pos - c;
}

inline float3 normalized_position(__global const float* in, uint row, uint in_off, uint in_ld, float lo_x, float lo_y,
                                  float lo_z, float inv_x, float inv_y, float inv_z) {
  const uint b = in_off + row * in_ld;
  return ((float3)(in[b], in[b + 1], in[b + 2]) - (float3)(lo_x, lo_y, lo_z)) * (float3)(inv_x, inv_y, inv_z);
}

// Trilinear weight of the cell corner at offset d ∈ {0, 1}³ for the fractional position t.
inline float corner_weight(uint3 d, float3 t) {
  return (d.x ? t.x : 1.0f - t.x) * (d.y ? t.y : 1.0f - t.y) * (d.z ? t.z : 1.0f - t.z);
}

// Work-item (row, level): out[row, out_col + level·F + f].
__kernel void hashgrid_forward(uint rows, uint levels, __global const float* in, uint in_off, uint in_ld, float lo_x,
                               float lo_y, float lo_z, float inv_x, float inv_y, float inv_z,
                               __global const uint4* level_info, __global const float* table, __global float* out,
                               uint out_off, uint out_ld) {
  const uint row = (uint)get_global_id(0);
  const uint l = (uint)get_global_id(1);
  if (row >= rows || l >= levels) return;
  const uint4 info = level_info[l];
  uint3 c;
  float3 t;
  grid_cell(normalized_position(in, row, in_off, in_ld, lo_x, lo_y, lo_z, inv_x, inv_y, inv_z), info.x, &c, &t);
  float acc[F];
  for (uint f = 0; f < F; ++f) acc[f] = 0.0f;
  for (uint corner = 0; corner < 8; ++corner) {
    const uint3 d = (uint3)(corner & 1, (corner >> 1) & 1, corner >> 2);
    const float w = corner_weight(d, t);
    __global const float* e = table + (size_t)(info.z + grid_index(c + d, info)) * F;
    for (uint f = 0; f < F; ++f) acc[f] = fma(w, e[f], acc[f]);
  }
  __global float* o = out + out_off + row * out_ld + l * F;
  for (uint f = 0; f < F; ++f) o[f] = acc[f];
}

// dL/dtable[e, f] += Σ_rows w_corner · dL/dout[row, level·F + f] (atomic: rows share vertices), and marks every
// entry a row reached in `touched`, so the optimiser can update only those (lazy Adam).
__kernel void hashgrid_backward(uint rows, uint levels, __global const float* in, uint in_off, uint in_ld, float lo_x,
                                float lo_y, float lo_z, float inv_x, float inv_y, float inv_z,
                                __global const uint4* level_info, __global const float* d_out, uint d_off, uint d_ld,
                                volatile __global GRAD_T* grad, __global uchar* touched) {
  const uint row = (uint)get_global_id(0);
  const uint l = (uint)get_global_id(1);
  if (row >= rows || l >= levels) return;
  const uint4 info = level_info[l];
  uint3 c;
  float3 t;
  grid_cell(normalized_position(in, row, in_off, in_ld, lo_x, lo_y, lo_z, inv_x, inv_y, inv_z), info.x, &c, &t);
  float g[F];
  __global const float* dr = d_out + d_off + row * d_ld + l * F;
  bool any = false;
  for (uint f = 0; f < F; ++f) {
    g[f] = dr[f];
    any = any || g[f] != 0.0f;
  }
  for (uint corner = 0; corner < 8; ++corner) {
    const uint3 d = (uint3)(corner & 1, (corner >> 1) & 1, corner >> 2);
    const float w = corner_weight(d, t);
    const uint e = info.z + grid_index(c + d, info);
    // Zero contributions are skipped: they change nothing and an uncontended table is much cheaper to update.
    if (w == 0.0f || !any) continue;
    touched[e] = 1;
    for (uint f = 0; f < F; ++f)
      if (g[f] != 0.0f) grad_add(grad + (size_t)e * F + f, w * g[f]);
  }
}
