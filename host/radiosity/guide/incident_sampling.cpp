#include "radiosity/guide/incident_sampling.hpp"

#include <algorithm>

#include "nn/programs.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/training_lights.hpp"

namespace clr::radiosity {

IncidentSampling::IncidentSampling(cl::Context& ctx) : ctx_(&ctx), vmf_(ctx) {}

void IncidentSampling::sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                              std::uint64_t step, const cl::Buffer<float>* lobes, TrainingBatch& batch) {
  if (settings.guide) decode(*lobes, batch);
  trace(geometry, settings, seed, step, batch);
  upload(settings, batch);
}

void IncidentSampling::upload_normals(const TrainingBatch& batch) {
  const std::size_t M = batch.points;
  const StageTimer timer(batch, &HostStageTimes::packing, ctx_);
  normals_host_.resize(M * 3);
  for (std::size_t m = 0; m < M; ++m) {
    const glm::vec3 n = frame_normal(batch.surface[m].point.frame.n, batch.wo[m]);
    std::copy_n(&n.x, 3, &normals_host_[3 * m]);
  }
  // The in-order queue runs a decode that read the previous normals before this write.
  put(normals_up_, normals_, normals_host_);
}

void IncidentSampling::decode(const cl::Buffer<float>& lobes, const TrainingBatch& batch) {
  upload_normals(batch);
  vmf_.decode(lobes, normals_, batch.points);
}

void IncidentSampling::set_lagged(bool lagged) {
  if (lagged && !sampling_) {
    sampling_ = std::make_unique<VmfMixture>(*ctx_);
    next_ = std::make_unique<VmfMixture>(*ctx_);
  } else if (!lagged) {
    sampling_.reset();
    next_.reset();
  }
  ahead_.reset();
}

void IncidentSampling::decode_sampling(const cl::Buffer<float>& raw, const TrainingBatch& batch) {
  upload_normals(batch);
  sampling_->decode(raw, normals_, batch.points);
}

void IncidentSampling::draw_ahead(const cl::Buffer<float>& raw, const TrainingBatch& next, std::uint64_t seed,
                                  std::uint64_t step) {
  collect_ahead();  // the directions of the step before, if its trace has not taken them yet
  const std::size_t M = next.points, N = next.samples;
  upload_normals(next);
  next_->decode(raw, normals_, M);
  draw(*next_, next, seed, step);
  ahead_read_.start(*ctx_, guided_, M * N * 3);
  ahead_ = Ahead{step, false};
}

void IncidentSampling::draw(VmfMixture& lobes, const TrainingBatch& batch, std::uint64_t seed, std::uint64_t step) {
  const std::size_t M = batch.points, N = batch.samples;
  guide_uniforms(M, N, seed, step, uniforms_host_, batch.first_point);
  put(uniforms_up_, uniforms_, uniforms_host_);
  ahead_read_.wait();  // a read of guided_ on the transfer queue finishes before the draw overwrites it
  cl::reserve(*ctx_, guided_, M * N * 3);
  lobes.sample(uniforms_, N, guided_);
}

void IncidentSampling::collect_ahead() {
  if (!ahead_ || ahead_->collected) return;
  const auto dirs = ahead_read_.result();
  guided_host_.assign(dirs.begin(), dirs.end());
  ahead_->collected = true;
}

void IncidentSampling::advance(std::uint64_t step) {
  if (drawn_ahead(step + 1)) std::swap(sampling_, next_);
}

void IncidentSampling::trace(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                             std::uint64_t step, TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
  std::span<const float> guided_dirs;
  if (guided(settings)) {
    const StageTimer timer(batch, &HostStageTimes::guide_read);
    if (drawn_ahead(step)) {
      collect_ahead();  // waits only for the device's work up to the draw, early in the step before
    } else {
      draw(sampler(), batch, seed, step);
      guided_host_.resize(M * N * 3);
      guided_.read(std::span<float>(guided_host_));
    }
    guided_dirs = guided_host_;
  }
  const geometry::LightSampler* lights = nullptr;
  if (settings.next_event) {
    if (lights_scene_ != &geometry.scene()) {
      lights_.emplace(training_light_sampler(geometry.scene()));
      lights_scene_ = &geometry.scene();
    }
    lights = &*lights_;
  }
  trace_incident(geometry, settings, seed, step, guided_dirs, batch, lights);
}

void IncidentSampling::upload(const BatchSettings& settings, const TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
  const StageTimer timer(batch, &HostStageTimes::uploads, ctx_);
  put(rows_up_, incident_rows, batch.incident_rows);
  put(weight_up_, weight, batch.weight);
  put(emitted_up_, emitted, batch.emitted);
  put(lookup_up_, lookup, batch.lookup);
  direct_points_ = batch.direct.empty() ? 0 : M;
  if (direct_points_) put(direct_up_, direct, batch.direct);
  if (settings.guide) {
    put(directions_up_, directions, batch.directions);
    put(bsdf_pdf_up_, bsdf_pdf, batch.bsdf_pdf);
    cl::reserve(*ctx_, pdf, M * N);
    cl::reserve(*ctx_, q_, M * N);
    sampler().mixture_pdf(directions, bsdf_pdf, N, settings.bsdf_fraction, pdf, q_);
  } else {
    put(pdf_up_, pdf, batch.pdf);
  }
}

void IncidentSampling::add_direct(cl::Buffer<float>& rhs, cl::Buffer<unsigned>& non_finite) {
  if (!direct_points_) return;
  if (!add_direct_) add_direct_ = ctx_->program(nn::programs::radiosity).kernel("add_direct");
  add_direct_->args(rhs, direct, unsigned(direct_points_), non_finite).launch(direct_points_);
}

}  // namespace clr::radiosity
