#include "radiosity/guide/incident_sampling.hpp"

#include <algorithm>

#include "nn/programs.hpp"
#include "radiosity/guide/i_module.hpp"

namespace clr::radiosity {

IncidentSampling::IncidentSampling(cl::Context& ctx) : ctx_(&ctx), vmf_(ctx) {}

void IncidentSampling::sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                              std::uint64_t step, const cl::Buffer<float>* lobes, TrainingBatch& batch) {
  if (settings.guide) decode(*lobes, batch);
  trace(geometry, settings, seed, step, batch);
  upload(settings, batch);
}

void IncidentSampling::decode(const cl::Buffer<float>& lobes, const TrainingBatch& batch) {
  const std::size_t M = batch.points;
  normals_host_.resize(M * 3);
  for (std::size_t m = 0; m < M; ++m) {
    const glm::vec3 n = frame_normal(batch.surface[m].point.frame.n, batch.wo[m]);
    std::copy_n(&n.x, 3, &normals_host_[3 * m]);
  }
  put(normals_up_, normals_, normals_host_);
  vmf_.decode(lobes, normals_, M);
}

void IncidentSampling::trace(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                             std::uint64_t step, TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
  guided_host_.clear();
  if (guided(settings)) {
    // A direction from the lobes for every sample; the host uses those of the samples that pick the guide.
    guide_uniforms(M, N, seed, step, uniforms_host_, batch.first_point);
    put(uniforms_up_, uniforms_, uniforms_host_);
    cl::reserve(*ctx_, guided_, M * N * 3);
    vmf_.sample(uniforms_, N, guided_);
    guided_host_.resize(M * N * 3);
    guided_.read(std::span<float>(guided_host_));
  }
  trace_incident(geometry, settings, seed, step, guided_host_, batch);
}

void IncidentSampling::upload(const BatchSettings& settings, const TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
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
    vmf_.mixture_pdf(directions, bsdf_pdf, N, settings.bsdf_fraction, pdf, q_);
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
