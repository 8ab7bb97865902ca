#pragma once
// The incident half of a batch (docs/design.md §2), shared by training and the residual metric, with the device's part
// here: the directions from the BSDF alone, or from the one-sample mixture p̃ = c·p_bsdf + (1 − c)·q with an
// I-Module's lobes — the lobes decoded in each point's frame and the guided directions drawn on the device, read
// back for the host's half (trace_incident: BSDF sampling and tracing), p̃ evaluated on the device — and the batch's
// per-sample arrays uploaded, ready for the right-hand side and the guide's loss.
#include <memory>
#include <optional>

#include "cl/async.hpp"
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
  // still forms q for the guide's loss), else from the BSDF alone (lobes unused). The three parts below in order.
  void sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed, std::uint64_t step,
              const cl::Buffer<float>* lobes, TrainingBatch& batch);

  // The parts of sample(), for the trainer's pipeline (docs/design.md §2), which traces ahead where nothing is
  // guided. decode: with settings.guide, the lobes in each point's frame (device). trace: the guided directions
  // drawn and read back where c < 1 (device, blocking: needs decode first), then BSDF sampling and tracing (host);
  // where c = 1 host work alone, which needs neither the lobes nor the device. upload: the batch's arrays to the
  // device and p̃ formed there; the arrays may change as soon as it returns.
  static bool guided(const BatchSettings& settings) { return settings.guide && settings.bsdf_fraction < 1.0f; }
  void decode(const cl::Buffer<float>& lobes, const TrainingBatch& batch);
  void trace(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed, std::uint64_t step,
             TrainingBatch& batch);
  void upload(const BatchSettings& settings, const TrainingBatch& batch);
  // Uploads as non-blocking writes from pinned host memory (the pipelined step), instead of blocking writes.
  void set_pinned_uploads(bool pinned) { pinned_ = pinned; }

  // The lagged guide (TrainConfig::guide_lag = 1, docs/design.md §2). Lobes then have three roles in a step: the
  // learner's (decode: the I-Module's forward at this step, which its loss trains — vmf()), the sampler's (the
  // lobes this step's directions were drawn from, so p̃'s), and the next step's (drawn early in this step and read
  // back while the device works). Without the lag the learner's lobes are the sampler's.
  void set_lagged(bool lagged);
  // Lagged: the sampler's lobes of this step, when none were drawn ahead for it (a session's first step).
  void decode_sampling(const cl::Buffer<float>& raw, const TrainingBatch& batch);
  // Lagged: the lobes of step `step` (raw [points × kVmfRaw] at `next`'s points) decoded, a direction drawn for
  // every sample, and their read back started without blocking; trace() of that step collects them.
  void draw_ahead(const cl::Buffer<float>& raw, const TrainingBatch& next, std::uint64_t seed, std::uint64_t step);
  bool drawn_ahead(std::uint64_t step) const { return ahead_ && ahead_->step == step; }
  // Lagged, after upload() of step `step`: the lobes drawn ahead for step + 1 become its sampler's.
  void advance(std::uint64_t step);

  // Device copies of the last batch's arrays (directions and bsdf_pdf only with lobes).
  cl::Buffer<float> incident_rows, weight, emitted, pdf, directions, bsdf_pdf;
  cl::Buffer<int> lookup;
  // With delta lights in the scene or next-event estimation: the points' next-event term (TrainingBatch::direct), added
  // to a right-hand side formed from these samples by add_direct; without them add_direct does nothing and no buffer
  // exists.
  cl::Buffer<float> direct;
  void add_direct(cl::Buffer<float>& rhs, cl::Buffer<unsigned>& non_finite);
  // The guide's view of those samples, once `radiance` holds sg(L_α) at the incident rows and `scattered` (× scale)
  // the N-Module's radiance at the points.
  GuideSamples guide_samples(const cl::Buffer<float>& radiance, const cl::Buffer<float>& scattered, float scale) const {
    return {directions, bsdf_pdf, pdf,       weight, emitted,
            lookup,     radiance, scattered, scale,  direct_points_ ? &direct : nullptr};
  }
  VmfMixture& vmf() { return vmf_; }

 private:
  template <typename T>
  void put(cl::PinnedUpload<T>& pinned, cl::Buffer<T>& dst, const std::vector<T>& host) {
    if (pinned_)
      pinned.send(*ctx_, dst, host);
    else
      cl::upload(*ctx_, dst, host);
  }

  void upload_normals(const TrainingBatch& batch);
  VmfMixture& sampler() { return sampling_ ? *sampling_ : vmf_; }
  // The directions drawn ahead, copied out of pinned memory (before the next draw reuses it) for their step.
  void collect_ahead();
  // A direction from `lobes` for every sample of `batch` into guided_, on the device; the host uses those of the
  // samples that pick the guide.
  void draw(VmfMixture& lobes, const TrainingBatch& batch, std::uint64_t seed, std::uint64_t step);

  cl::Context* ctx_;
  VmfMixture vmf_;
  // The light sampler of next-event estimation, built for the first batch that asks for it, and kept for its scene.
  std::optional<geometry::LightSampler> lights_;
  const scene::Scene* lights_scene_ = nullptr;
  bool pinned_ = false;
  // Lagged only: the sampler's lobes and the next step's (swapped by advance()).
  std::unique_ptr<VmfMixture> sampling_, next_;
  struct Ahead {
    std::uint64_t step;
    bool collected;
  };
  std::optional<Ahead> ahead_;  // the step whose directions were drawn ahead
  cl::PinnedDownload<float> ahead_read_;
  std::vector<float> normals_host_, uniforms_host_, guided_host_;
  std::size_t direct_points_ = 0;         // points in `direct`; 0 when the last batch had no delta lights
  std::optional<cl::Kernel> add_direct_;  // built on first use
  cl::Buffer<float> normals_, uniforms_, guided_, q_;
  cl::PinnedUpload<float> normals_up_, uniforms_up_, rows_up_, weight_up_, emitted_up_, pdf_up_, directions_up_,
      bsdf_pdf_up_, direct_up_;
  cl::PinnedUpload<int> lookup_up_;
};

}  // namespace clr::radiosity
