// The I-Module's sampling distribution (DESIGN.md §2, §7): a mixture of VMF_LOBES von Mises–Fisher lobes on the
// sphere of directions, read from the network's VMF_RAW raw outputs per point. Lobe k owns raw[4k .. 4k+3]:
//   λ = softmax(a) over the lobes, κ = exp(clamp(b + ln κ₀, ln κ_min, ln κ_max)), θ = π·σ(c + c₀), φ = 2π·σ(d),
//   μ = sin θ cos φ · t + sin θ sin φ · s + cos θ · n  in the point's frame (vmf_frame) about its normal n.
// Angles, not a normalised 3-vector: four numbers a lobe is what fits the paper's 32 outputs for 8 lobes (a 3-vector
// needs 40), and σ keeps them in range without a normalisation whose gradient blows up near the origin.
// Why a frame about the normal, and the offsets κ₀, c₀: an untrained network's outputs are near 0, which then means
// lobes of κ = 3 at 36° from the normal — a cosine-like spread over the hemisphere the light comes from — rather
// than κ = 1 lobes about the horizon in world space, which sent half of the guided samples below one-sided
// surfaces and made the untrained guide 2.5× noisier than BSDF sampling.
// Everything is float32 and stable over κ ∈ [κ_min, κ_max] = [1e-4, 1e4] (raw values outside the clamp, ±inf
// included, land on its ends): expm1/log1p forms, a series where a derivative cancels, log-sum-exp over lobes (never
// a division by a q that may underflow). Host twin: tests/nn/vmf_twin.hpp.
#define VMF_LOBES 8
#define VMF_RAW 32
#define VMF_LOG_KAPPA_MIN (-9.2103404f)  // κ ≥ 1e-4
#define VMF_LOG_KAPPA_MAX 9.2103404f     // κ ≤ 1e4
#define VMF_LOG_4PI 2.5310242f
#define VMF_PI 3.14159265358979f
#define VMF_LOG_KAPPA0 1.0986123f  // ln 3
#define VMF_C0 (-1.3862944f)       // σ(c₀) = 0.2: θ = 36°

// A tangent frame (t, s) about the unit normal n that varies continuously with n — a learned φ means the same
// direction at neighbouring points — except in a cap around ±VMF_FRAME_AXIS, an axis off every coordinate plane
// where no axis-aligned wall's normal lies (every frame field on the sphere has such a point).
inline void vmf_frame(float3 n, float3* t, float3* s) {
  float3 c = cross((float3)(0.48f, 0.6f, 0.64f), n);
  if (dot(c, c) < 1e-4f) c = cross((float3)(0.8f, -0.6f, 0.0f), n);  // ⟂ the axis
  *t = normalize(c);
  *s = cross(n, *t);
}

inline float vmf_sigmoid(float x) { return 1.0f / (1.0f + exp(-x)); }

// log of the normalisation κ / (2π (1 − e^{−2κ})) = log(−2κ / expm1(−2κ)) − log 4π. With expm1 the ratio stays
// exact to float rounding down to κ_min = 1e-4 (the clamp keeps κ = 0 and 0/0 out), where it is 1 + κ.
inline float vmf_log_norm(float kappa) { return log(-2.0f * kappa / expm1(-2.0f * kappa)) - VMF_LOG_4PI; }

// κ ∂log norm/∂κ + κ = 1 − 2κ / expm1(2κ) (κ ∂log v/∂κ = κ(μ·ω − 1) + this); series κ − κ²/3 + κ⁴/45 below 0.05,
// where the closed form cancels.
inline float vmf_dlognorm_dlogkappa(float kappa) {
  if (kappa < 0.05f) return kappa - kappa * kappa / 3.0f + kappa * kappa * kappa * kappa / 45.0f;
  return 1.0f - 2.0f * kappa / expm1(2.0f * kappa);
}

// A point's lobes are decoded once per step (all the transcendental work of the activations) into VMF_LOBE_FLOATS
// floats a lobe, so that sampling, evaluating and differentiating at many directions reads them:
#define VMF_LOBE_FLOATS 16
#define VMF_L_LOGC 0     // log λ + log norm(κ): log(λ v(ω)) = LOGC + κ (μ·ω − 1)
#define VMF_L_KAPPA 1    // κ
#define VMF_L_MU 2       // μ (3)
#define VMF_L_LAMBDA 5   // λ
#define VMF_L_DKAPPA 6   // 1 − 2κ/expm1(2κ)
#define VMF_L_FREE 7     // 1 where b is inside the clamp of log κ, 0 where the clamp holds it (no gradient)
#define VMF_L_DMU_DC 8   // κ ∂μ/∂c = κ ∂μ/∂θ · π σ'(c)  (3)
#define VMF_L_DMU_DD 11  // κ ∂μ/∂d = κ ∂μ/∂φ · 2π σ'(d) (3)

// normals: the point's frame normal (3 floats a point): its shading normal on the side ω_o is on.
__kernel void vmf_decode(__global const float* raw, __global const float* normals, uint points, __global float* lobes) {
  const size_t m = get_global_id(0);
  if (m >= points) return;
  __global const float* r = raw + m * VMF_RAW;
  const float3 n = vload3(m, normals);
  float3 t, tb;
  vmf_frame(n, &t, &tb);
  float amax = r[0];
  for (int k = 1; k < VMF_LOBES; ++k) amax = fmax(amax, r[4 * k]);
  float sum = 0.0f;
  for (int k = 0; k < VMF_LOBES; ++k) sum += exp(r[4 * k] - amax);
  const float lse = amax + log(sum);
  for (int k = 0; k < VMF_LOBES; ++k) {
    __global float* l = lobes + (m * VMF_LOBES + k) * VMF_LOBE_FLOATS;
    const float b = r[4 * k + 1] + VMF_LOG_KAPPA0;
    const float kappa = exp(clamp(b, VMF_LOG_KAPPA_MIN, VMF_LOG_KAPPA_MAX));
    const float sc = vmf_sigmoid(r[4 * k + 2] + VMF_C0), sd = vmf_sigmoid(r[4 * k + 3]);
    float ct, cp;
    const float st = sincos(VMF_PI * sc, &ct), sp = sincos(2.0f * VMF_PI * sd, &cp);
    const float log_lambda = r[4 * k] - lse;
    l[VMF_L_LOGC] = log_lambda + vmf_log_norm(kappa);
    l[VMF_L_KAPPA] = kappa;
    vstore3(st * cp * t + st * sp * tb + ct * n, 0, l + VMF_L_MU);
    l[VMF_L_LAMBDA] = exp(log_lambda);
    l[VMF_L_DKAPPA] = vmf_dlognorm_dlogkappa(kappa);
    l[VMF_L_FREE] = b > VMF_LOG_KAPPA_MIN && b < VMF_LOG_KAPPA_MAX ? 1.0f : 0.0f;
    vstore3(kappa * VMF_PI * sc * (1.0f - sc) * (ct * cp * t + ct * sp * tb - st * n), 0, l + VMF_L_DMU_DC);
    vstore3(kappa * 2.0f * VMF_PI * sd * (1.0f - sd) * (st * cp * tb - st * sp * t), 0, l + VMF_L_DMU_DD);
    l[14] = l[15] = 0.0f;
  }
}

// μ·ω − 1 = −|μ − ω|²/2 for unit vectors: exact where it matters, near the mean of a sharp lobe, where 1 − μ·ω
// rounds to a multiple of 2⁻²⁴ (κ = 1e4 then loses 1e-4 of the lobe's mass).
inline float vmf_cos_minus_one(float3 mu, float3 w) {
  const float3 d = mu - w;
  return -0.5f * dot(d, d);
}

// log(λ_k v_k(ω)) for every lobe of a point into terms, and log q(ω) (log-sum-exp: q may underflow, its log not).
inline float vmf_mixture_log_pdf(__global const float* lobes, float3 w, float* terms) {
  float tmax = -INFINITY;
  for (int k = 0; k < VMF_LOBES; ++k) {
    __global const float* l = lobes + k * VMF_LOBE_FLOATS;
    terms[k] = l[VMF_L_LOGC] + l[VMF_L_KAPPA] * vmf_cos_minus_one(vload3(0, l + VMF_L_MU), w);
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
// cancellation near the mean (it tends to −2·u1 as κ → 0, accurate at κ_min); sin θ = sqrt(−r (r + 2)).
inline float3 vmf_sample_lobe(float kappa, float3 mu, float u1, float u2) {
  const float r = clamp(log1p(u1 * expm1(-2.0f * kappa)) / kappa, -2.0f, 0.0f);
  const float st = sqrt(fmax(0.0f, -r * (r + 2.0f)));
  const float phi = 2.0f * VMF_PI * u2;
  float3 t, b;
  vmf_basis(mu, &t, &b);
  return normalize(st * cos(phi) * t + st * sin(phi) * b + (1.0f + r) * mu);
}

// One direction per (point, sample) from the point's mixture: u[3s] picks the lobe, u[3s+1], u[3s+2] place it.
__kernel void vmf_sample(__global const float* lobes, __global const float* u, uint points, uint samples,
                         __global float* dirs) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  __global const float* l = lobes + (s / samples) * VMF_LOBES * VMF_LOBE_FLOATS;
  const float u0 = u[3 * s];
  int k = 0;
  float cdf = l[VMF_L_LAMBDA];
  while (k < VMF_LOBES - 1 && u0 >= cdf) cdf += l[++k * VMF_LOBE_FLOATS + VMF_L_LAMBDA];
  l += k * VMF_LOBE_FLOATS;
  vstore3(vmf_sample_lobe(l[VMF_L_KAPPA], vload3(0, l + VMF_L_MU), u[3 * s + 1], u[3 * s + 2]), s, dirs);
}

// The one-sample mixture density each sample was drawn with (DESIGN.md §2): p̃ = c·p_bsdf + (1 − c)·q(ω), and
// q(ω) itself. bsdf_pdf < 0 marks a sample of a delta lobe: never guided, drawn with probability c (its weight
// already holds the lobe's discrete probability), so p̃ = c and q = 0 there.
__kernel void vmf_mixture_pdf(__global const float* lobes, __global const float* dirs, __global const float* bsdf_pdf,
                              uint points, uint samples, float bsdf_fraction, __global float* pdf, __global float* q) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  if (bsdf_pdf[s] < 0.0f) {
    pdf[s] = bsdf_fraction;
    q[s] = 0.0f;
    return;
  }
  float terms[VMF_LOBES];
  const float qs =
      exp(vmf_mixture_log_pdf(lobes + (s / samples) * VMF_LOBES * VMF_LOBE_FLOATS, vload3(s, dirs), terms));
  q[s] = qs;
  pdf[s] = bsdf_fraction * bsdf_pdf[s] + (1.0f - bsdf_fraction) * qs;
}

// ∂log q(ω)/∂raw for one point's 32 raw outputs, through the responsibilities r_k = λ_k v_k / q (log-sum-exp):
//   ∂/∂a_j = r_j − λ_j;  ∂/∂b_j = r_j (κ_j (μ_j·ω − 1) + 1 − 2κ_j/expm1(2κ_j)) inside the clamp, 0 outside;
//   ∂/∂c_j = r_j κ_j (ω·∂μ/∂θ) π σ'(c_j);  ∂/∂d_j = r_j κ_j (ω·∂μ/∂φ) 2π σ'(d_j).
// Writes it to grad[0..31] and returns log q(ω).
inline float vmf_dlogq_at(__global const float* lobes, float3 w, float* grad) {
  float terms[VMF_LOBES];
  const float lq = vmf_mixture_log_pdf(lobes, w, terms);
  for (int k = 0; k < VMF_LOBES; ++k) {
    __global const float* l = lobes + k * VMF_LOBE_FLOATS;
    const float r = exp(terms[k] - lq), kappa = l[VMF_L_KAPPA];
    grad[4 * k] = r - l[VMF_L_LAMBDA];
    grad[4 * k + 1] = l[VMF_L_FREE] * r * (kappa * vmf_cos_minus_one(vload3(0, l + VMF_L_MU), w) + l[VMF_L_DKAPPA]);
    grad[4 * k + 2] = r * dot(w, vload3(0, l + VMF_L_DMU_DC));
    grad[4 * k + 3] = r * dot(w, vload3(0, l + VMF_L_DMU_DD));
  }
  return lq;
}

// dlogq[s·32 ..] = ∂log q(ω_s)/∂raw of the sample's point: what the finite-difference tests check directly.
__kernel void vmf_dlogq(__global const float* lobes, __global const float* dirs, uint points, uint samples,
                        __global float* dlogq) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  float grad[VMF_RAW];
  vmf_dlogq_at(lobes + (s / samples) * VMF_LOBES * VMF_LOBE_FLOATS, vload3(s, dirs), grad);
  for (int i = 0; i < VMF_RAW; ++i) dlogq[s * VMF_RAW + i] = grad[i];
}
