// The sparse exchange of a hash table's gradient between MPI ranks (host/distributed/gradient_exchange.cpp): a
// step touches a small share of the table, so ranks swap which entries they touched as a bitmap (one bit an entry)
// and then only the gradient rows of the union, packed. GRAD_T is the gradient's type: float, or long for the
// deterministic fixed-point mode, whose sums are exact in any order.

// Bit b of word w is the touched flag of entry 32·w + b.
__kernel void touched_bits(uint entries, __global const uchar* touched, __global uint* bits) {
  const uint w = (uint)get_global_id(0);
  if (w >= (entries + 31u) / 32u) return;
  uint word = 0u;
  const uint first = 32u * w, last = min(entries, first + 32u);
  for (uint e = first; e < last; ++e)
    if (touched[e]) word |= 1u << (e - first);
  bits[w] = word;
}

// packed[r·F + f] = grad[index[r]·F + f]
__kernel void gather_rows(uint rows, uint features, __global const uint* index, __global const GRAD_T* grad,
                          __global GRAD_T* packed) {
  const uint r = (uint)get_global_id(0);
  if (r >= rows) return;
  const uint e = index[r];
  for (uint f = 0u; f < features; ++f) packed[r * features + f] = grad[e * features + f];
}

// The reverse, and the row joins the step's touched set: lazy Adam then updates the same entries on every rank.
__kernel void scatter_rows(uint rows, uint features, __global const uint* index, __global const GRAD_T* packed,
                           __global GRAD_T* grad, __global uchar* touched) {
  const uint r = (uint)get_global_id(0);
  if (r >= rows) return;
  const uint e = index[r];
  for (uint f = 0u; f < features; ++f) grad[e * features + f] = packed[r * features + f];
  touched[e] = (uchar)1;
}
