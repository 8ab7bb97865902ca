// The right-hand side of the rendering-equation residual (docs/design.md §2) for M points with N incident samples each:
//   rhs[m] = (1/N) Σ_n (E[m,n] + w[m,n] · L[lookup[m,n]]) / p̃[m,n]
// w = f·cos times the throughput of any delta chain the sample passed (RGB); E = the emission (or environment)
// the sample met, already weighted the same way, so emission part-way along a chain is exact; p̃ = the density the
// direction was drawn with (for a delta lobe, whose weight already holds its discrete probability, the share of
// samples that take the BSDF); L = N-Module
// radiance at the samples that end on a modelled surface (lookup = row in L, or -1 where none). The network is
// evaluated on the compacted rows only, so samples that need no lookup cost nothing there. Non-finite terms are dropped
// and counted.
__kernel void incident_rhs(__global const float* weight, __global const float* emitted, __global const float* pdf,
                           __global const int* lookup, __global const float* radiance, unsigned int points,
                           unsigned int samples, __global float* rhs, volatile __global unsigned int* non_finite) {
  const size_t m = get_global_id(0);
  if (m >= points) return;
  float3 sum = (float3)(0.0f);
  for (unsigned int n = 0; n < samples; ++n) {
    const size_t s = m * samples + n;
    float3 term = vload3(s, emitted);
    const int row = lookup[s];
    if (row >= 0) term += vload3(s, weight) * vload3((size_t)row, radiance);
    term /= pdf[s];
    if (isfinite(term.x) && isfinite(term.y) && isfinite(term.z))
      sum += term;
    else
      atomic_inc(non_finite);
  }
  vstore3(sum / (float)samples, m, rhs);
}

// Light from delta emitters (point, spot, directional, projector), which no sampled direction reaches: the host's
// next-event estimate at each point, summed over the lights with shadow rays, added to its right-hand side as a
// constant (radiosity/training_batch.hpp: `direct`). Launched only for scenes that have such lights. A non-finite
// term is dropped and counted, as incident_rhs drops its samples.
__kernel void add_direct(__global float* rhs, __global const float* direct, unsigned int points,
                         volatile __global unsigned int* non_finite) {
  const size_t m = get_global_id(0);
  if (m >= points) return;
  const float3 d = vload3(m, direct);
  if (isfinite(d.x) && isfinite(d.y) && isfinite(d.z))
    vstore3(vload3(m, rhs) + d, m, rhs);
  else
    atomic_inc(non_finite);
}
