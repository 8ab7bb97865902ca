// The I-Module's loss and its gradient w.r.t. the raw lobe outputs (ISNR §4.1–4.2). Needs atomics.cl and vmf.cl.
// For point m with N samples ω_n drawn from p̃ (the one-sample mixture), from the N-Module's own incident radiance:
//   t_n = lum(f·cos·L_i(ω_n))   (emitted + weight·sg(L_α), the weights not divided by any pdf)
//   F = lum(sg(L_α(x, ω_o)) − D),  p_n = t_n / F  — the target density
// F = ∫ f·cos·L_i dω over the sampled directions is what the N-Module predicts at the point itself (it models the
// scattered radiance), as the paper's §4.3 computes it, less D, the next-event term (use_direct: the delta lights' and,
// with next-event estimation, the light samples' MIS-weighted mean), which L_α includes but the sampled directions'
// terms do not carry (their emission is MIS-weighted): the guide learns where the rest comes from. An
// estimate from the N samples instead (self-normalised) was measured to teach little: a point's one lit sample always
// got p/p̃ = N whatever its radiance.
//   KL  (Eq. 17): ∇ = −(1/N) Σ p_n/p̃_n ∇log q(ω_n)
//   IKL (Eq. 20): each term times (2·1[p_n > q_n] − 1), the sign of log(p/q): the integrand's absolute value.
// sg(L_α) and sg(p̃) hold by construction: only the raw outputs receive a gradient. Delta samples (bsdf_pdf < 0)
// are not part of q's domain and are skipped. `scale` (1/M for a mean over points) multiplies the gradient and the
// loss, Σ (1/N) p/p̃ · log(p/q) (or its absolute value), summed into `total` (one atomic a work-group). Non-finite
// samples are dropped and counted.
#define GUIDE_MAX_WEIGHT 1024.0f

inline float guide_luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

inline float guide_target(size_t s, __global const float* weight, __global const float* emitted,
                          __global const int* lookup, __global const float* radiance) {
  float3 li = vload3(s, emitted);
  const int row = lookup[s];
  if (row >= 0) li += vload3(s, weight) * vload3((size_t)row, radiance);
  return guide_luminance(li);
}

// Point m's gradient into d_raw; returns its share of the loss (0 where it is not finite).
inline float guide_point(size_t m, uint samples, __global const float* lobes, __global const float* dirs,
                         __global const float* bsdf_pdf, __global const float* pdf, __global const float* weight,
                         __global const float* emitted, __global const int* lookup, __global const float* radiance,
                         __global const float* scattered, float scattered_scale, __global const float* direct,
                         uint use_direct, uint improved, float scale, __global float* d_raw,
                         volatile __global uint* non_finite) {
  __global const float* lp = vmf_point_lobes(lobes, m);
  float8 ga = 0.0f, gb = 0.0f, gc = 0.0f, gd = 0.0f;  // the gradient of the lobes' raw a, b, c, d

  // F_s = (1/N) Σ t/p̃, the samples' own estimate of F, bounds F from below at F_s/GUIDE_MAX_WEIGHT: then a point's
  // weights Σ p/p̃/N = F_s/F stay ≤ GUIDE_MAX_WEIGHT where the N-Module underestimates F badly (untrained, or
  // emitters near FLT_MAX), whose unbounded weights otherwise carried overflow into the I-Module's parameters. The
  // bound is loose on purpose: a rare sample that finds a lamp earns a weight of ~1/(N·its probability), and a
  // bound of N cut what the guide learned alone on Veach Bidir (docs/results/isnr.md, "The I-Module's sampler
  // alone").
  uint bad = 0;
  float f_samples = 0.0f;
  for (uint n = 0; n < samples; ++n) {
    const size_t s = m * samples + n;
    if (bsdf_pdf[s] >= 0.0f) f_samples += guide_target(s, weight, emitted, lookup, radiance) / pdf[s];
  }
  float f_point = scattered_scale * guide_luminance(vload3(m, scattered));
  if (use_direct) f_point -= guide_luminance(vload3(m, direct));
  const float F = fmax(f_point, f_samples / ((float)samples * GUIDE_MAX_WEIGHT));
  if (!isfinite(F)) ++bad;
  float loss = 0.0f;
  // F = 0: the N-Module sees no light arrive, so there is no target density to learn.
  if (F > 0.0f && isfinite(F)) {
    for (uint n = 0; n < samples; ++n) {
      const size_t s = m * samples + n;
      if (bsdf_pdf[s] < 0.0f) continue;
      const float p = guide_target(s, weight, emitted, lookup, radiance) / F;
      const float w = p / pdf[s] / (float)samples;  // p / p̃, and the 1/N of the estimate
      if (w == 0.0f) continue;                      // t = 0 adds nothing
      if (!(isfinite(w) && w > 0.0f)) {
        ++bad;
        continue;
      }
      float8 da, db, dc, dd;
      const float log_ratio = log(p) - vmf_dlogq_at(lp, vload3(s, dirs), &da, &db, &dc, &dd);
      const float g = -scale * w * (improved && !(log_ratio > 0.0f) ? -1.0f : 1.0f);
      ga += g * da;
      gb += g * db;
      gc += g * dc;
      gd += g * dd;
      loss += w * (improved ? fabs(log_ratio) : log_ratio);
    }
  }
  const bool finite = isfinite(loss) && all(isfinite(ga) && isfinite(gb) && isfinite(gc) && isfinite(gd));
  if (!finite) ++bad;
  if (!finite) ga = gb = gc = gd = 0.0f;
  vmf_store_raw(ga, gb, gc, gd, d_raw + m * VMF_RAW);
  if (bad) atomic_add(non_finite, bad);
  return finite ? scale * loss : 0.0f;
}

// One work-item a point; the group size is a power of two and `scratch` holds a float a work-item (the loss's sum).
__kernel void guide_loss(uint points, uint samples, __global const float* lobes, __global const float* dirs,
                         __global const float* bsdf_pdf, __global const float* pdf, __global const float* weight,
                         __global const float* emitted, __global const int* lookup, __global const float* radiance,
                         __global const float* scattered, float scattered_scale, __global const float* direct,
                         uint use_direct, uint improved, float scale, __global float* d_raw,
                         volatile __global float* total, volatile __global uint* non_finite, __local float* scratch) {
  const size_t m = get_global_id(0);
  const float loss =
      m < points ? guide_point(m, samples, lobes, dirs, bsdf_pdf, pdf, weight, emitted, lookup, radiance, scattered,
                               scattered_scale, direct, use_direct, improved, scale, d_raw, non_finite)
                 : 0.0f;
  group_add_f32(total, loss, scratch);
}
