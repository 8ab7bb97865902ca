// The I-Module's sampling distribution (docs/design.md §2, §7): a mixture of VMF_LOBES von Mises–Fisher lobes on the
// sphere of directions, read from the network's VMF_RAW raw outputs per point. Lobe k owns raw[4k .. 4k+3]:
//   λ = softmax(a) over the lobes, κ = exp(clamp(b + ln κ₀, ln κ_min, ln κ_max)), θ = π·σ(c + c₀), φ = 2π·σ(d),
//   μ = sin θ cos φ · t + sin θ sin φ · s + cos θ · n  in the point's frame (vmf_frame) about its normal n.
// Angles, not a normalised 3-vector: four numbers a lobe is what fits the paper's 32 outputs for 8 lobes (a 3-vector
// needs 40), and σ keeps them in range without a normalisation whose gradient blows up near the origin.
// Why a frame about the normal, and the offsets κ₀, c₀: an untrained network's outputs are near 0, which then means
// lobes of κ = 3 at 36° from the normal — a cosine-like spread over the hemisphere the light comes from — rather
// than κ = 1 lobes about the horizon in world space, which sent half of the guided samples below one-sided
// surfaces and made the untrained guide noisier than BSDF sampling (docs/method.md, docs/results/isnr.md).
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

inline float8 vmf_sigmoid(float8 x) { return 1.0f / (1.0f + exp(-x)); }

// log of the normalisation κ / (2π (1 − e^{−2κ})) = log(−2κ / expm1(−2κ)) − log 4π. With expm1 the ratio stays
// exact to float rounding down to κ_min = 1e-4 (the clamp keeps κ = 0 and 0/0 out), where it is 1 + κ.
inline float8 vmf_log_norm(float8 kappa) { return log(-2.0f * kappa / expm1(-2.0f * kappa)) - VMF_LOG_4PI; }

// κ ∂log norm/∂κ + κ = 1 − 2κ / expm1(2κ) (κ ∂log v/∂κ = κ(μ·ω − 1) + this); series κ − κ²/3 + κ⁴/45 below 0.05,
// where the closed form cancels.
inline float8 vmf_dlognorm_dlogkappa(float8 kappa) {
  const float8 k2 = kappa * kappa;
  return select(1.0f - 2.0f * kappa / expm1(2.0f * kappa), kappa - k2 / 3.0f + k2 * k2 / 45.0f, kappa < 0.05f);
}

// A point's lobes are decoded once per step (all the transcendental work of the activations) into VMF_LOBE_FIELDS
// fields, each a float8 over the 8 lobes (field f of point m at lobes + (m·VMF_LOBE_FIELDS + f)·8), so that sampling,
// evaluating and differentiating at many directions read them — and so that every activation, log-sum-exp and
// gradient runs on float8: on CPU devices one vector exp/log/sincos does the 8 lobes' work at once (a lobe at a
// time was scalar libm calls, and the decode cost many times the I-Module MLP's forward: docs/results/isnr.md).
#define VMF_LOBE_FIELDS 14
#define VMF_L_LOGC 0     // log λ + log norm(κ): log(λ v(ω)) = LOGC + κ (μ·ω − 1)
#define VMF_L_KAPPA 1    // κ
#define VMF_L_MU 2       // μ: x, y, z
#define VMF_L_LAMBDA 5   // λ
#define VMF_L_DKAPPA 6   // 1 − 2κ/expm1(2κ)
#define VMF_L_FREE 7     // 1 where b is inside the clamp of log κ, 0 where the clamp holds it (no gradient)
#define VMF_L_DMU_DC 8   // κ ∂μ/∂c = κ ∂μ/∂θ · π σ'(c): x, y, z
#define VMF_L_DMU_DD 11  // κ ∂μ/∂d = κ ∂μ/∂φ · 2π σ'(d): x, y, z

inline __global const float* vmf_point_lobes(__global const float* lobes, size_t m) {
  return lobes + m * VMF_LOBE_FIELDS * VMF_LOBES;
}
inline float8 vmf_field(__global const float* lp, int f) { return vload8(f, lp); }
inline float vmf_hmax(float8 v) {
  const float4 a = fmax(v.lo, v.hi);
  return fmax(fmax(a.x, a.y), fmax(a.z, a.w));
}
inline float vmf_hsum(float8 v) {
  const float4 a = v.lo + v.hi;
  return (a.x + a.y) + (a.z + a.w);
}

// The raw outputs of a point, lobe k at raw[4k + j], and its gradient written back in the same order.
inline void vmf_store_raw(float8 a, float8 b, float8 c, float8 d, __global float* out) {
  vstore16((float16)(a.s0, b.s0, c.s0, d.s0, a.s1, b.s1, c.s1, d.s1, a.s2, b.s2, c.s2, d.s2, a.s3, b.s3, c.s3, d.s3), 0,
           out);
  vstore16((float16)(a.s4, b.s4, c.s4, d.s4, a.s5, b.s5, c.s5, d.s5, a.s6, b.s6, c.s6, d.s6, a.s7, b.s7, c.s7, d.s7), 1,
           out);
}

// normals: the point's frame normal (3 floats a point): its shading normal on the side ω_o is on.
__kernel void vmf_decode(__global const float* raw, __global const float* normals, uint points, __global float* lobes) {
  const size_t m = get_global_id(0);
  if (m >= points) return;
  const float16 r0 = vload16(0, raw + m * VMF_RAW), r1 = vload16(1, raw + m * VMF_RAW);
  const float8 a = (float8)(r0.s048c, r1.s048c), b = (float8)(r0.s159d, r1.s159d) + VMF_LOG_KAPPA0,
               c = (float8)(r0.s26ae, r1.s26ae), d = (float8)(r0.s37bf, r1.s37bf);
  const float3 n = vload3(m, normals);
  float3 t, tb;
  vmf_frame(n, &t, &tb);
  const float amax = vmf_hmax(a);
  const float8 e = exp(a - amax);
  const float sum = vmf_hsum(e);
  const float8 kappa = exp(clamp(b, VMF_LOG_KAPPA_MIN, VMF_LOG_KAPPA_MAX));
  const float8 sc = vmf_sigmoid(c + VMF_C0), sd = vmf_sigmoid(d);
  float8 ct, cp;
  const float8 st = sincos(VMF_PI * sc, &ct), sp = sincos(2.0f * VMF_PI * sd, &cp);
  __global float* lp = lobes + m * VMF_LOBE_FIELDS * VMF_LOBES;
  vstore8(a - (amax + log(sum)) + vmf_log_norm(kappa), VMF_L_LOGC, lp);
  vstore8(kappa, VMF_L_KAPPA, lp);
  const float8 stcp = st * cp, stsp = st * sp;
  vstore8(stcp * t.x + stsp * tb.x + ct * n.x, VMF_L_MU, lp);
  vstore8(stcp * t.y + stsp * tb.y + ct * n.y, VMF_L_MU + 1, lp);
  vstore8(stcp * t.z + stsp * tb.z + ct * n.z, VMF_L_MU + 2, lp);
  vstore8(e / sum, VMF_L_LAMBDA, lp);
  vstore8(vmf_dlognorm_dlogkappa(kappa), VMF_L_DKAPPA, lp);
  vstore8(select((float8)(0.0f), (float8)(1.0f), b > VMF_LOG_KAPPA_MIN && b < VMF_LOG_KAPPA_MAX), VMF_L_FREE, lp);
  const float8 kc = kappa * VMF_PI * sc * (1.0f - sc), kd = kappa * 2.0f * VMF_PI * sd * (1.0f - sd);
  const float8 ctcp = ct * cp, ctsp = ct * sp;
  vstore8(kc * (ctcp * t.x + ctsp * tb.x - st * n.x), VMF_L_DMU_DC, lp);
  vstore8(kc * (ctcp * t.y + ctsp * tb.y - st * n.y), VMF_L_DMU_DC + 1, lp);
  vstore8(kc * (ctcp * t.z + ctsp * tb.z - st * n.z), VMF_L_DMU_DC + 2, lp);
  vstore8(kd * (stcp * tb.x - stsp * t.x), VMF_L_DMU_DD, lp);
  vstore8(kd * (stcp * tb.y - stsp * t.y), VMF_L_DMU_DD + 1, lp);
  vstore8(kd * (stcp * tb.z - stsp * t.z), VMF_L_DMU_DD + 2, lp);
}

// μ·ω − 1 = −|μ − ω|²/2 for unit vectors, per lobe: exact where it matters, near the mean of a sharp lobe, where
// 1 − μ·ω rounds to a multiple of 2⁻²⁴ (κ = 1e4 then loses 1e-4 of the lobe's mass).
inline float8 vmf_cos_minus_one(__global const float* lp, float3 w) {
  const float8 dx = vmf_field(lp, VMF_L_MU) - w.x, dy = vmf_field(lp, VMF_L_MU + 1) - w.y,
               dz = vmf_field(lp, VMF_L_MU + 2) - w.z;
  return -0.5f * (dx * dx + dy * dy + dz * dz);
}

// log(λ_k v_k(ω)) for every lobe of a point into terms, and log q(ω) (log-sum-exp: q may underflow, its log not).
inline float vmf_mixture_log_pdf(__global const float* lp, float3 w, float8* terms) {
  *terms = vmf_field(lp, VMF_L_LOGC) + vmf_field(lp, VMF_L_KAPPA) * vmf_cos_minus_one(lp, w);
  const float tmax = vmf_hmax(*terms);
  return tmax + log(vmf_hsum(exp(*terms - tmax)));
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
  __global const float* lp = vmf_point_lobes(lobes, s / samples);
  __global const float* lambda = lp + VMF_L_LAMBDA * VMF_LOBES;
  const float u0 = u[3 * s];
  int k = 0;
  float cdf = lambda[0];
  while (k < VMF_LOBES - 1 && u0 >= cdf) cdf += lambda[++k];
  const float3 mu =
      (float3)(lp[VMF_L_MU * VMF_LOBES + k], lp[(VMF_L_MU + 1) * VMF_LOBES + k], lp[(VMF_L_MU + 2) * VMF_LOBES + k]);
  vstore3(vmf_sample_lobe(lp[VMF_L_KAPPA * VMF_LOBES + k], mu, u[3 * s + 1], u[3 * s + 2]), s, dirs);
}

// The one-sample mixture density each sample was drawn with (docs/design.md §2): p̃ = c·p_bsdf + (1 − c)·q(ω), and
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
  float8 terms;
  const float qs = exp(vmf_mixture_log_pdf(vmf_point_lobes(lobes, s / samples), vload3(s, dirs), &terms));
  q[s] = qs;
  pdf[s] = bsdf_fraction * bsdf_pdf[s] + (1.0f - bsdf_fraction) * qs;
}

// ∂log q(ω)/∂raw for one point's 32 raw outputs, through the responsibilities r_k = λ_k v_k / q (log-sum-exp):
//   ∂/∂a_j = r_j − λ_j;  ∂/∂b_j = r_j (κ_j (μ_j·ω − 1) + 1 − 2κ_j/expm1(2κ_j)) inside the clamp, 0 outside;
//   ∂/∂c_j = r_j κ_j (ω·∂μ/∂θ) π σ'(c_j);  ∂/∂d_j = r_j κ_j (ω·∂μ/∂φ) 2π σ'(d_j).
// Writes the four float8 (all lobes' a, b, c, d) and returns log q(ω).
inline float vmf_dlogq_at(__global const float* lp, float3 w, float8* ga, float8* gb, float8* gc, float8* gd) {
  float8 terms;
  const float lq = vmf_mixture_log_pdf(lp, w, &terms);
  const float8 r = exp(terms - lq), kappa = vmf_field(lp, VMF_L_KAPPA);
  *ga = r - vmf_field(lp, VMF_L_LAMBDA);
  *gb = vmf_field(lp, VMF_L_FREE) * r * (kappa * vmf_cos_minus_one(lp, w) + vmf_field(lp, VMF_L_DKAPPA));
  *gc = r * (w.x * vmf_field(lp, VMF_L_DMU_DC) + w.y * vmf_field(lp, VMF_L_DMU_DC + 1) +
             w.z * vmf_field(lp, VMF_L_DMU_DC + 2));
  *gd = r * (w.x * vmf_field(lp, VMF_L_DMU_DD) + w.y * vmf_field(lp, VMF_L_DMU_DD + 1) +
             w.z * vmf_field(lp, VMF_L_DMU_DD + 2));
  return lq;
}

// dlogq[s·32 ..] = ∂log q(ω_s)/∂raw of the sample's point: what the finite-difference tests check directly.
__kernel void vmf_dlogq(__global const float* lobes, __global const float* dirs, uint points, uint samples,
                        __global float* dlogq) {
  const size_t s = get_global_id(0);
  if (s >= (size_t)points * samples) return;
  float8 ga, gb, gc, gd;
  vmf_dlogq_at(vmf_point_lobes(lobes, s / samples), vload3(s, dirs), &ga, &gb, &gc, &gd);
  vmf_store_raw(ga, gb, gc, gd, dlogq + s * VMF_RAW);
}
