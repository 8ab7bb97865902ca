#include "radiosity/guide/incident_sampling.hpp"

#include <algorithm>

#include "nn/programs.hpp"
#include "radiosity/guide/i_module.hpp"

namespace clr::radiosity {

IncidentSampling::IncidentSampling(cl::Context& ctx) : ctx_(&ctx), vmf_(ctx) {}

void IncidentSampling::sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                              std::uint64_t step, const cl::Buffer<float>* lobes, TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
  const bool guided = settings.guide && settings.bsdf_fraction < 1.0f;
  guided_host_.clear();
  if (settings.guide) {
    normals_host_.resize(M * 3);
    for (std::size_t m = 0; m < M; ++m) {
      const glm::vec3 n = frame_normal(batch.surface[m].point.frame.n, batch.wo[m]);
      std::copy_n(&n.x, 3, &normals_host_[3 * m]);
    }
    cl::upload(*ctx_, normals_, normals_host_);
    vmf_.decode(*lobes, normals_, M);
  }
  if (guided) {
    // A direction from the lobes for every sample; the host uses those of the samples that pick the guide.
    guide_uniforms(M, N, seed, step, uniforms_host_, batch.first_point);
    cl::upload(*ctx_, uniforms_, uniforms_host_);
    cl::reserve(*ctx_, guided_, M * N * 3);
    vmf_.sample(uniforms_, N, guided_);
    guided_host_.resize(M * N * 3);
    guided_.read(std::span<float>(guided_host_));
  }
  trace_incident(geometry, settings, seed, step, guided_host_, batch);
  cl::upload(*ctx_, incident_rows, batch.incident_rows);
  cl::upload(*ctx_, weight, batch.weight);
  cl::upload(*ctx_, emitted, batch.emitted);
  cl::upload(*ctx_, lookup, batch.lookup);
  direct_points_ = batch.direct.empty() ? 0 : M;
  if (direct_points_) cl::upload(*ctx_, direct, batch.direct);
  if (settings.guide) {
    cl::upload(*ctx_, directions, batch.directions);
    cl::upload(*ctx_, bsdf_pdf, batch.bsdf_pdf);
    cl::reserve(*ctx_, pdf, M * N);
    cl::reserve(*ctx_, q_, M * N);
    vmf_.mixture_pdf(directions, bsdf_pdf, N, settings.bsdf_fraction, pdf, q_);
  } else {
    cl::upload(*ctx_, pdf, batch.pdf);
  }
}

void IncidentSampling::add_direct(cl::Buffer<float>& rhs, cl::Buffer<unsigned>& non_finite) {
  if (!direct_points_) return;
  if (!add_direct_) add_direct_ = ctx_->program(nn::programs::radiosity).kernel("add_direct");
  add_direct_->args(rhs, direct, unsigned(direct_points_), non_finite).launch(direct_points_);
}

}  // namespace clr::radiosity
