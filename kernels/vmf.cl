// The I-Module's sampling distribution (DESIGN.md §2, §7): a mixture of VMF_LOBES von Mises–Fisher lobes on the
// sphere of world directions, read from the network's VMF_RAW raw outputs per point. Lobe k owns raw[4k .. 4k+3]:
//   λ = softmax(a) over the lobes, κ = exp(clamp(b, ln κ_min, ln κ_max)), θ = π·σ(c), φ = 2π·σ(d),
//   μ = (sin θ cos φ, sin θ sin φ, cos θ).
// Angles, not a normalised 3-vector: four numbers a lobe is what fits the paper's 32 outputs for 8 lobes (a 3-vector
// needs 40), and σ keeps them in range without a normalisation whose gradient blows up near the origin.
// Everything is float32 and stable over κ ∈ [0, κ_max]: expm1/log1p forms, a series near κ = 0, log-sum-exp over
// lobes (never a division by a q that may underflow). Host twin: tests/nn/vmf_twin.hpp.
#define VMF_LOBES 8
#define VMF_RAW 32
#define VMF_LOG_KAPPA_MIN (-9.2103404f)  // κ ≥ 1e-4
#define VMF_LOG_KAPPA_MAX 9.2103404f     // κ ≤ 1e4
#define VMF_LOG_4PI 2.5310242f
#define VMF_PI 3.14159265358979f

typedef struct {
  float log_lambda[VMF_LOBES];
  float kappa[VMF_LOBES];
  float3 mu[VMF_LOBES];
} vmf_mixture;

inline float vmf_sigmoid(float x) { return 1.0f / (1.0f + exp(-x)); }

inline float3 vmf_mean_direction(float c, float d) {
  const float theta = VMF_PI * vmf_sigmoid(c), phi = 2.0f * VMF_PI * vmf_sigmoid(d);
  const float st = sin(theta);
  return (float3)(st * cos(phi), st * sin(phi), cos(theta));
}

inline vmf_mixture vmf_decode(__global const float* raw) {
  vmf_mixture m;
  float amax = raw[0];
  for (int k = 1; k < VMF_LOBES; ++k) amax = fmax(amax, raw[4 * k]);
  float sum = 0.0f;
  for (int k = 0; k < VMF_LOBES; ++k) sum += exp(raw[4 * k] - amax);
  const float lse = amax + log(sum);
  for (int k = 0; k < VMF_LOBES; ++k) {
    m.log_lambda[k] = raw[4 * k] - lse;
    m.kappa[k] = exp(clamp(raw[4 * k + 1], VMF_LOG_KAPPA_MIN, VMF_LOG_KAPPA_MAX));
    m.mu[k] = vmf_mean_direction(raw[4 * k + 2], raw[4 * k + 3]);
  }
  return m;
}

// log of the normalisation κ / (2π (1 − e^{−2κ})) = log(−2κ / expm1(−2κ)) − log 4π; → −log 4π as κ → 0.
inline float vmf_log_norm(float kappa) {
  if (kappa < 1e-6f) return kappa - VMF_LOG_4PI;  // log(1 + κ + O(κ²))
  return log(-2.0f * kappa / expm1(-2.0f * kappa)) - VMF_LOG_4PI;
}

// log v(ω) = log norm + κ (μ·ω − 1): the exponent is ≤ 0, so nothing overflows at κ_max.
inline float vmf_log_pdf(float kappa, float3 mu, float3 w) {
  return vmf_log_norm(kappa) + kappa * (fmin(dot(mu, w), 1.0f) - 1.0f);
}

// log q(ω) of the mixture, and each lobe's log(λ_k v_k(ω)) into terms.
inline float vmf_mixture_log_pdf(const vmf_mixture* m, float3 w, float* terms) {
  float tmax = -INFINITY;
  for (int k = 0; k < VMF_LOBES; ++k) {
    terms[k] = m->log_lambda[k] + vmf_log_pdf(m->kappa[k], m->mu[k], w);
    tmax = fmax(tmax, terms[k]);
  }
  float sum = 0.0f;
  for (int k = 0; k < VMF_LOBES; ++k) sum += exp(terms[k] - tmax);
  return tmax + log(sum);
}

// Duff et al. 2017: an orthonormal basis (t, b) around a unit n, without a branch on the pole.
inline void vmf_basis(float3 n, float3* t, float3* b) {
  const float s = copysign(1.0f, n.z);
  const float a = -1.0f / (s + n.z);
  const float c = n.x * n.y * a;
  *t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = (float3)(c, s + n.y * n.y * a, -n.y);
}

// A direction from one lobe: r = cos θ − 1 = log1p(u1 · expm1(−2κ)) / κ inverts the CDF of cos θ without
// cancellation near the mean (−2·u1 as κ → 0); sin θ = sqrt(−r (r + 2)).
inline float3 vmf_sample_lobe(float kappa, float3 mu, float u1, float u2) {
  float r = kappa < 1e-6f ? -2.0f * u1 : log1p(u1 * expm1(-2.0f * kappa)) / kappa;
  r = clamp(r, -2.0f, 0.0f);
  const float st = sqrt(fmax(0.0f, -r * (r + 2.0f)));
  const float phi = 2.0f * VMF_PI * u2;
  float3 t, b;
  vmf_basis(mu, &t, &b);
  return normalize(st * cos(phi) * t + st * sin(phi) * b + (1.0f + r) * mu);
}

// One direction per (point, sample) from the point's mixture: u[3s] picks the lobe, u[3s+1], u[3s+2] place it.
__kernel void vmf_sample(__global const float* raw, __global const float* u, uint points, uint samples,
                         __global float* dirs) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  const vmf_mixture m = vmf_decode(raw + (s / samples) * VMF_RAW);
  const float u0 = u[3 * s];
  int k = 0;
  float cdf = exp(m.log_lambda[0]);
  while (k < VMF_LOBES - 1 && u0 >= cdf) cdf += exp(m.log_lambda[++k]);
  vstore3(vmf_sample_lobe(m.kappa[k], m.mu[k], u[3 * s + 1], u[3 * s + 2]), s, dirs);
}

// The one-sample mixture density each sample was drawn with (DESIGN.md §2): p̃ = c·p_bsdf + (1 − c)·q(ω), and
// q(ω) itself. bsdf_pdf < 0 marks a sample of a delta lobe: never guided, drawn with probability c (its weight
// already holds the lobe's discrete probability), so p̃ = c and q = 0 there.
__kernel void vmf_mixture_pdf(__global const float* raw, __global const float* dirs, __global const float* bsdf_pdf,
                              uint points, uint samples, float bsdf_fraction, __global float* pdf, __global float* q) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  if (bsdf_pdf[s] < 0.0f) {
    pdf[s] = bsdf_fraction;
    q[s] = 0.0f;
    return;
  }
  const vmf_mixture m = vmf_decode(raw + (s / samples) * VMF_RAW);
  float terms[VMF_LOBES];
  const float qs = exp(vmf_mixture_log_pdf(&m, vload3(s, dirs), terms));
  q[s] = qs;
  pdf[s] = bsdf_fraction * bsdf_pdf[s] + (1.0f - bsdf_fraction) * qs;
}

// 1 − κ coth κ + κ = 1 − 2κ / expm1(2κ), the κ-derivative part of κ ∂log v/∂κ that does not involve ω;
// series κ − κ²/3 + κ⁴/45 below 0.05, where the closed form cancels.
inline float vmf_dlognorm_dlogkappa(float kappa) {
  if (kappa < 0.05f) return kappa - kappa * kappa / 3.0f + kappa * kappa * kappa * kappa / 45.0f;
  return 1.0f - 2.0f * kappa / expm1(2.0f * kappa);
}

// ∂log q(ω)/∂raw for one point's 32 raw outputs, through the responsibilities r_k = λ_k v_k / q (log-sum-exp):
//   ∂/∂a_j = r_j − λ_j;  ∂/∂b_j = r_j (κ_j (μ_j·ω − 1) + 1 − 2κ_j/expm1(2κ_j)) inside the clamp, 0 outside;
//   ∂/∂c_j = r_j κ_j (ω·∂μ/∂θ) π σ'(c_j);  ∂/∂d_j = r_j κ_j (ω·∂μ/∂φ) 2π σ'(d_j).
// Writes it to grad[0..31] and returns log q(ω).
inline float vmf_dlogq_at(__global const float* raw, const vmf_mixture* m, float3 w, float* grad) {
  float terms[VMF_LOBES];
  const float lq = vmf_mixture_log_pdf(m, w, terms);
  for (int k = 0; k < VMF_LOBES; ++k) {
    const float r = exp(terms[k] - lq), kappa = m->kappa[k];
    grad[4 * k] = r - exp(m->log_lambda[k]);
    const float b = raw[4 * k + 1];
    const bool inside = b > VMF_LOG_KAPPA_MIN && b < VMF_LOG_KAPPA_MAX;
    grad[4 * k + 1] =
        inside ? r * (kappa * (fmin(dot(m->mu[k], w), 1.0f) - 1.0f) + vmf_dlognorm_dlogkappa(kappa)) : 0.0f;
    const float sc = vmf_sigmoid(raw[4 * k + 2]), sd = vmf_sigmoid(raw[4 * k + 3]);
    const float theta = VMF_PI * sc, phi = 2.0f * VMF_PI * sd;
    const float ct = cos(theta), st = sin(theta), cp = cos(phi), sp = sin(phi);
    const float3 dmu_dtheta = (float3)(ct * cp, ct * sp, -st), dmu_dphi = (float3)(-st * sp, st * cp, 0.0f);
    grad[4 * k + 2] = r * kappa * dot(w, dmu_dtheta) * VMF_PI * sc * (1.0f - sc);
    grad[4 * k + 3] = r * kappa * dot(w, dmu_dphi) * 2.0f * VMF_PI * sd * (1.0f - sd);
  }
  return lq;
}

// dlogq[s·32 ..] = ∂log q(ω_s)/∂raw of the sample's point: what the finite-difference tests check directly.
__kernel void vmf_dlogq(__global const float* raw, __global const float* dirs, uint points, uint samples,
                        __global float* dlogq) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  __global const float* rp = raw + (s / samples) * VMF_RAW;
  const vmf_mixture m = vmf_decode(rp);
  float grad[VMF_RAW];
  vmf_dlogq_at(rp, &m, vload3(s, dirs), grad);
  for (int i = 0; i < VMF_RAW; ++i) dlogq[s * VMF_RAW + i] = grad[i];
}
