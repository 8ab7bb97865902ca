#pragma once
// The incident half of a batch (docs/design.md §2), shared by training and the residual metric, with the device's part
// here: the directions from the BSDF alone, or from the one-sample mixture p̃ = c·p_bsdf + (1 − c)·q with an
// I-Module's lobes — the lobes decoded in each point's frame and the guided directions drawn on the device, read
// back for the host's half (trace_incident: BSDF sampling and tracing), p̃ evaluated on the device — and the batch's
// per-sample arrays uploaded, ready for the right-hand side and the guide's loss.
#include <optional>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "radiosity/guide/vmf_mixture.hpp"
#include "radiosity/training_batch.hpp"

namespace clr::radiosity {

class IncidentSampling {
 public:
  explicit IncidentSampling(cl::Context& ctx);

  // After sample_training_points filled `batch`'s points: draws its incident half, with settings.guide from the
  // mixture with `lobes` ([points × 32] raw I-Module outputs on the device; c = 1 draws from the BSDF alone but
  // still forms q for the guide's loss), else from the BSDF alone (lobes unused).
  void sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed, std::uint64_t step,
              const cl::Buffer<float>* lobes, TrainingBatch& batch);

  // Device copies of the last batch's arrays (directions and bsdf_pdf only with lobes).
  cl::Buffer<float> incident_rows, weight, emitted, pdf, directions, bsdf_pdf;
  cl::Buffer<int> lookup;
  // With delta lights in the scene: the points' next-event term (TrainingBatch::direct), added to a right-hand side
  // formed from these samples by add_direct; without them add_direct does nothing and no buffer exists.
  cl::Buffer<float> direct;
  void add_direct(cl::Buffer<float>& rhs, cl::Buffer<unsigned>& non_finite);
  // The guide's view of those samples, once `radiance` holds sg(L_α) at the incident rows and `scattered` (× scale)
  // the N-Module's radiance at the points.
  GuideSamples guide_samples(const cl::Buffer<float>& radiance, const cl::Buffer<float>& scattered, float scale) const {
    return {directions, bsdf_pdf, pdf, weight, emitted, lookup, radiance, scattered, scale};
  }
  VmfMixture& vmf() { return vmf_; }

 private:
  cl::Context* ctx_;
  VmfMixture vmf_;
  std::vector<float> normals_host_, uniforms_host_, guided_host_;
  std::size_t direct_points_ = 0;         // points in `direct`; 0 when the last batch had no delta lights
  std::optional<cl::Kernel> add_direct_;  // built on first use
  cl::Buffer<float> normals_, uniforms_, guided_, q_;
};

}  // namespace clr::radiosity
