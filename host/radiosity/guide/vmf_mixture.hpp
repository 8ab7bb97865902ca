#pragma once
// The I-Module's head (ISNR §4.1–4.2; kernels/vmf.cl, kernels/guide.cl): a mixture of kVmfLobes von Mises–Fisher
// lobes per point, read from kVmfRaw raw network outputs (the activations are documented in vmf.cl). Sampling,
// the one-sample mixture density p̃ = c·p_bsdf + (1 − c)·q, ∂log q/∂raw, and the KL / Improved-KL gradient that
// trains the I-Module from the N-Module's incident radiance. Per-sample buffers are [points · samples (× 3)],
// sample s belonging to point s / samples.
#include <cstddef>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "nn/loss.hpp"

namespace clr::radiosity {

inline constexpr std::size_t kVmfLobes = 8, kVmfRaw = 32;

// What the guide's loss reads of a training step's samples on the device (TrainingBatch's per-sample layouts).
struct GuideSamples {
  const cl::Buffer<float>& dirs;      // ω_i, world space
  const cl::Buffer<float>& bsdf_pdf;  // p_bsdf(ω_i), < 0 for a delta-lobe sample (not in q's domain)
  const cl::Buffer<float>& pdf;       // p̃(ω_i), the density the sample was drawn with
  const cl::Buffer<float>& weight;    // RGB f·cos (× delta-chain throughput), not divided by a pdf
  const cl::Buffer<float>& emitted;   // RGB, weighted as `weight`
  const cl::Buffer<int>& lookup;      // row of `radiance`, or −1
  const cl::Buffer<float>& radiance;  // sg(L_α) at the incident hits
  // sg(L_α(x, ω_o)) at the points (RGB), times scattered_scale in radiance: F = ∫ f·cos·L_i, the normalisation
  // of the target density.
  const cl::Buffer<float>& scattered;
  float scattered_scale = 1.0f;
  // The next-event term at the points (RGB radiance: delta lights, the light samples' mean), part of L_α but not of
  // the sampled integral the guide learns: F is L_α less it. Null where there is none.
  const cl::Buffer<float>* direct = nullptr;
};

class VmfMixture {
 public:
  explicit VmfMixture(cl::Context& ctx);

  // Decodes the raw outputs [points × kVmfRaw] into lobes (all the activations' transcendental work, once per
  // step), in the frame about each point's normal [points × 3] (frame_normal); the calls below read the lobes of
  // the last decode.
  void decode(const cl::Buffer<float>& raw, const cl::Buffer<float>& normals, std::size_t points);
  // One direction per sample from its point's mixture; u holds 3 uniforms in [0, 1) per sample.
  void sample(const cl::Buffer<float>& u, std::size_t samples, cl::Buffer<float>& dirs);
  // p̃ and q at every sample's direction (bsdf_fraction 0 and bsdf_pdf ≥ 0 make p̃ = q).
  void mixture_pdf(const cl::Buffer<float>& dirs, const cl::Buffer<float>& bsdf_pdf, std::size_t samples,
                   float bsdf_fraction, cl::Buffer<float>& pdf, cl::Buffer<float>& q);
  // out[s · kVmfRaw + i] = ∂log q(ω_s)/∂raw_i of the sample's point.
  void dlogq(const cl::Buffer<float>& dirs, std::size_t samples, cl::Buffer<float>& out);
  // d_raw [points × kVmfRaw] = gradient of the mean over points of the KL (improved = false, Eq. 17) or IKL
  // (Eq. 20) estimate; the loss value accumulates on the device until take(). Enqueues only. `mean_over` (0: the
  // decoded points) is the batch the mean is over: an MPI rank holds a share of it, and the ranks' sums are the mean.
  void loss(const GuideSamples& s, std::size_t samples, bool improved, cl::Buffer<float>& d_raw,
            std::size_t mean_over = 0);
  // Reads and resets the accumulated loss and the count of dropped non-finite samples (a sync point).
  nn::LossValue take();

 private:
  cl::Context* ctx_;
  std::size_t points_ = 0;
  cl::Buffer<float> lobes_;  // [points × 14 fields × kVmfLobes], kernels/vmf.cl
  cl::Buffer<float> total_;
  cl::Buffer<std::uint32_t> non_finite_;
  cl::Kernel decode_, sample_, pdf_, dlogq_, loss_;
};

}  // namespace clr::radiosity
