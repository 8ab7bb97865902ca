#pragma once
// The host half of one training step (docs/design.md §2), built in two halves around the I-Module: first M points
// (x, ω_o) drawn uniformly by area and direction on the surfaces the network models; then N incident directions
// each — from the BSDF, or, with ISNR, from the one-sample mixture p̃ = c·p_bsdf + (1 − c)·q whose guided
// directions the device drew — traced through delta chains to the next modelled surface. What the device needs
// comes out as flat arrays; the network is evaluated only on the `incident` rows (compacted), never on rays that
// escaped or died.
#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "cl/context.hpp"
#include "geometry/light_sampler.hpp"
#include "geometry/surface_sampler.hpp"
#include "radiosity/surface_query.hpp"

namespace clr::radiosity {

// Host time of a batch's stages, summed over the steps that filled it (bench_guide, bench_pipeline: a host that
// cannot keep up with the device shows here on any machine). Wall seconds, except the *_cpu parts of the incident
// loop, which are its threads' CPU seconds summed (what other processes' load does not inflate).
struct HostStageTimes {
  double points = 0;      // sample_training_points: points, ω_o, their input rows
  double guide_read = 0;  // the guided directions drawn and read back: the host waits for the device's work before
  double incident = 0;    // the incident loop: BSDF sampling, tracing, next-event terms …
  // … split by thread time; next_event_cpu: delta lights and light samples with their shadow rays
  double bsdf_cpu = 0, tracing_cpu = 0, next_event_cpu = 0;
  double packing = 0;  // lookup rows compacted, p̃ without a guide, the lobes' frames
  double uploads = 0;  // the batch's arrays handed to the device (blocking writes, or copies into pinned memory)
  // Blocked until the device freed pinned memory for reuse (the device is behind the host), out of the stages above.
  double device_wait = 0;
  std::size_t steps = 0;

  // The host's own work; guide_read and device_wait are waiting for the device.
  double host_work() const { return points + incident + packing + uploads; }
};

struct TrainingBatch {
  std::size_t points = 0, samples = 0;
  std::size_t first_point = 0;                   // index of points[0] in the step's point sequence
  std::vector<geometry::SurfaceSample> surface;  // points: where L_α is trained …
  std::vector<Vec3> wo;                          // … and from which direction
  std::vector<float> point_rows;                 // points × kRawInputs
  std::vector<float> incident_rows;              // lookups × kRawInputs: where sg(L_α) is read
  // Per sample (points·samples, × 3 for RGB and directions). A sample's RHS term is (emitted + weight·L) / pdf.
  std::vector<float> weight;      // f·cos times the delta chain's throughput; not divided by any pdf, except for
                                  // samples of a delta lobe, which hold the BSDF's weight (f / lobe probability)
  std::vector<float> emitted;     // the emission met along the chain, weighted as `weight`
  std::vector<float> bsdf_pdf;    // p_bsdf(ω_i); −1 marks a delta-lobe (or absorbed) sample: never guided
  std::vector<float> pdf;         // p̃: filled here when nothing is guided (c = 1), else on the device
  std::vector<float> directions;  // ω_i, world space; only with a guide (its pdf and loss need them)
  std::vector<int> lookup;        // row in incident_rows, or −1
  // Per point (× 3): the next-event term added to the point's RHS — f·cos·radiance summed over the scene's delta
  // lights (point, spot, directional, projector), which no sampled direction can reach, with shadow rays, plus, with
  // next-event estimation, the mean of the light samples' MIS-weighted estimates. Empty when there is neither. Not
  // part of the samples' terms, so the I-Module learns the rest: what the directions must find.
  std::vector<float> direct;
  // Per sample (× 3), with next-event estimation: the light sample drawn beside it, whose mean over the point's samples
  // is in `direct` (kept on the host for the residual metric's variance); else empty.
  std::vector<float> light;
  std::size_t guided = 0;           // samples whose direction came from q
  HostStageTimes* times = nullptr;  // where the stages that fill this batch add their time; null: not timed

  std::size_t lookups() const { return incident_rows.size() / nn::kRawInputs; }
};

// Adds the wall time of its scope to one of a batch's stages (nothing when the batch is not timed); with `ctx`, the
// part spent blocked on the device's pinned memory goes to device_wait instead.
class StageTimer {
 public:
  StageTimer(const TrainingBatch& batch, double HostStageTimes::*stage, const cl::Context* ctx = nullptr)
      : times_(batch.times), stage_(stage), ctx_(ctx), waited_(ctx ? ctx->waited_seconds() : 0.0) {}
  ~StageTimer() {
    if (!times_) return;
    const double all = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double waited = ctx_ ? ctx_->waited_seconds() - waited_ : 0.0;
    times_->*stage_ += all - waited;
    times_->device_wait += waited;
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  HostStageTimes* times_;
  double HostStageTimes::*stage_;
  const cl::Context* ctx_;
  double waited_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

struct BatchSettings {
  std::size_t points = 4096;
  std::size_t samples = 4;
  int max_delta_bounces = 8;
  float bsdf_fraction = 1.0f;  // c: the share of directions drawn from the BSDF; 1 = BSDF sampling only
  // An I-Module learns from the batch (ISNR): directions and p_bsdf are kept for its loss and p̃ is formed on the
  // device, also while c = 1 (the guide's warm-up, when it learns from BSDF samples before any are drawn from it).
  bool guide = false;
  // Next-event estimation of area lights and the environment beside each sample (TrainConfig::nee).
  bool next_event = false;
  // This process's points are [first_point, first_point + points) of the step's sequence: every stream is keyed
  // by a point's index in it, so MPI ranks drawing their shares draw the one-process batch between them.
  std::size_t first_point = 0;

  // The trainer's pipeline checks that a batch prepared ahead was drawn with the settings of the step it serves.
  bool operator==(const BatchSettings&) const = default;
};

// The first half, on the host: points, directions ω_o, their raw input rows.
void sample_training_points(const geometry::SurfaceSampler& sampler, const scene::Scene& scene,
                            const BatchSettings& settings, std::uint64_t seed, std::uint64_t step,
                            TrainingBatch& batch);

// The second half, on the host: each sample takes the BSDF with probability c, else the direction guided[s] (3
// floats per sample, drawn from q on the device; empty when c = 1), and its ray is traced (Embree) through delta
// chains; with delta lights, each point's `direct` term is formed too, and with `lights` (training_light_sampler: given
// when settings.next_event) a light sample beside each direction. Sample streams depend only on (seed, step, point
// index), so a batch is reproducible whatever the thread count, and the light samples have a stream of their own, so
// the directions are the same with or without them. IncidentSampling (guide/incident_sampling.hpp) runs the device's
// part around it.
void trace_incident(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                    std::uint64_t step, std::span<const float> guided, TrainingBatch& batch,
                    const geometry::LightSampler* lights = nullptr);

// The three uniforms per sample that the device turns into guided directions (kernels/vmf.cl: vmf_sample).
void guide_uniforms(std::size_t points, std::size_t samples, std::uint64_t seed, std::uint64_t step,
                    std::vector<float>& u, std::size_t first_point = 0);

}  // namespace clr::radiosity
