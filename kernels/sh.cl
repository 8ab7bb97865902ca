// Real spherical harmonics of bands 0-3 (16 coefficients; "degree 4" in tiny-cuda-nn's naming) of a unit direction,
// with the signs and constants of tiny-cuda-nn's SphericalHarmonics encoding. Directions are used as given (the
// scene supplies unit vectors), so the gradient is that of the polynomials below.
inline void sh16(float x, float y, float z, float* o) {
  const float xy = x * y, xz = x * z, yz = y * z, x2 = x * x, y2 = y * y, z2 = z * z;
  o[0] = 0.28209479177387814f;
  o[1] = -0.48860251190291987f * y;
  o[2] = 0.48860251190291987f * z;
  o[3] = -0.48860251190291987f * x;
  o[4] = 1.0925484305920792f * xy;
  o[5] = -1.0925484305920792f * yz;
  o[6] = 0.94617469575755997f * z2 - 0.31539156525251999f;
  o[7] = -1.0925484305920792f * xz;
  o[8] = 0.54627421529603959f * (x2 - y2);
  o[9] = 0.59004358992664352f * y * (-3.0f * x2 + y2);
  o[10] = 2.8906114426405538f * xy * z;
  o[11] = 0.45704579946446572f * y * (1.0f - 5.0f * z2);
  o[12] = 0.3731763325901154f * z * (5.0f * z2 - 3.0f);
  o[13] = 0.45704579946446572f * x * (1.0f - 5.0f * z2);
  o[14] = 1.4453057213202769f * z * (x2 - y2);
  o[15] = 0.59004358992664352f * x * (-x2 + 3.0f * y2);
}

__kernel void sh_forward(uint rows, __global const float* in, uint in_off, uint in_ld, __global float* out,
                         uint out_off, uint out_ld) {
  const uint r = (uint)get_global_id(0);
  if (r >= rows) return;
  __global const float* d = in + in_off + r * in_ld;
  float o[16];
  sh16(d[0], d[1], d[2], o);
  __global float* dst = out + out_off + r * out_ld;
  for (uint j = 0; j < 16; ++j) dst[j] = o[j];
}

// d_in[r, 0..2] = Σ_j d_out[r, j] · ∂Y_j/∂(x, y, z).
__kernel void sh_backward(uint rows, __global const float* in, uint in_off, uint in_ld, __global const float* d_out,
                          uint d_off, uint d_ld, __global float* d_in, uint di_off, uint di_ld) {
  const uint r = (uint)get_global_id(0);
  if (r >= rows) return;
  __global const float* d = in + in_off + r * in_ld;
  __global const float* g = d_out + d_off + r * d_ld;
  const float x = d[0], y = d[1], z = d[2];
  const float c1 = 0.48860251190291987f, c4 = 1.0925484305920792f, c6 = 0.94617469575755997f, c8 = 0.54627421529603959f,
              c9 = 0.59004358992664352f, c10 = 2.8906114426405538f, c11 = 0.45704579946446572f,
              c12 = 0.3731763325901154f, c14 = 1.4453057213202769f;
  float gx = 0.0f, gy = 0.0f, gz = 0.0f;
  gy += g[1] * -c1;
  gz += g[2] * c1;
  gx += g[3] * -c1;
  gx += g[4] * c4 * y;
  gy += g[4] * c4 * x;
  gy += g[5] * -c4 * z;
  gz += g[5] * -c4 * y;
  gz += g[6] * c6 * 2.0f * z;
  gx += g[7] * -c4 * z;
  gz += g[7] * -c4 * x;
  gx += g[8] * c8 * 2.0f * x;
  gy += g[8] * -c8 * 2.0f * y;
  gx += g[9] * c9 * -6.0f * x * y;
  gy += g[9] * c9 * 3.0f * (y * y - x * x);
  gx += g[10] * c10 * y * z;
  gy += g[10] * c10 * x * z;
  gz += g[10] * c10 * x * y;
  gy += g[11] * c11 * (1.0f - 5.0f * z * z);
  gz += g[11] * c11 * -10.0f * y * z;
  gz += g[12] * c12 * (15.0f * z * z - 3.0f);
  gx += g[13] * c11 * (1.0f - 5.0f * z * z);
  gz += g[13] * c11 * -10.0f * x * z;
  gx += g[14] * c14 * 2.0f * x * z;
  gy += g[14] * c14 * -2.0f * y * z;
  gz += g[14] * c14 * (x * x - y * y);
  gx += g[15] * c9 * 3.0f * (y * y - x * x);
  gy += g[15] * c9 * 6.0f * x * y;
  __global float* o = d_in + di_off + r * di_ld;
  o[0] = gx;
  o[1] = gy;
  o[2] = gz;
}

// Raw features passed through: out[r, out_col + j] = in[r, in_col + j] for j < cols.
__kernel void copy_columns(uint rows, uint cols, __global const float* in, uint in_off, uint in_ld, __global float* out,
                           uint out_off, uint out_ld) {
  const uint j = (uint)get_global_id(0);
  const uint r = (uint)get_global_id(1);
  if (r >= rows || j >= cols) return;
  out[out_off + r * out_ld + j] = in[in_off + r * in_ld + j];
}
