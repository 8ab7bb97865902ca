#include "radiosity/incident_sampling.hpp"

namespace clr::radiosity {
namespace {

// Grow-only device buffers: re-created only when a batch needs more elements than before.
template <typename T>
void upload(cl::Context& ctx, cl::Buffer<T>& buf, const std::vector<T>& host) {
  if (buf.size() < std::max<std::size_t>(1, host.size()))
    buf = cl::Buffer<T>(ctx, std::max<std::size_t>(1, host.size()));
  if (!host.empty()) buf.write(host);
}
template <typename T>
void reserve(cl::Context& ctx, cl::Buffer<T>& buf, std::size_t count) {
  if (buf.size() < count) buf = cl::Buffer<T>(ctx, count);
}

}  // namespace

IncidentSampling::IncidentSampling(cl::Context& ctx) : ctx_(&ctx), vmf_(ctx) {}

void IncidentSampling::sample(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                              std::uint64_t step, const cl::Buffer<float>* lobes, TrainingBatch& batch) {
  const std::size_t M = batch.points, N = batch.samples;
  const bool guided = lobes && settings.bsdf_fraction < 1.0f;
  BatchSettings s = settings;
  if (!guided) s.bsdf_fraction = 1.0f;
  guided_host_.clear();
  if (guided) {
    // A direction from the lobes for every sample; the host uses those of the samples that pick the guide.
    vmf_.decode(*lobes, M);
    guide_uniforms(M, N, seed, step, uniforms_host_);
    upload(*ctx_, uniforms_, uniforms_host_);
    reserve(*ctx_, guided_, M * N * 3);
    vmf_.sample(uniforms_, N, guided_);
    guided_host_.resize(M * N * 3);
    guided_.read(std::span<float>(guided_host_));
  }
  sample_incident(geometry, s, seed, step, guided_host_, batch);
  upload(*ctx_, incident_rows, batch.incident_rows);
  upload(*ctx_, weight, batch.weight);
  upload(*ctx_, emitted, batch.emitted);
  upload(*ctx_, lookup, batch.lookup);
  if (guided) {
    upload(*ctx_, directions, batch.directions);
    upload(*ctx_, bsdf_pdf, batch.bsdf_pdf);
    reserve(*ctx_, pdf, M * N);
    reserve(*ctx_, q_, M * N);
    vmf_.mixture_pdf(directions, bsdf_pdf, N, s.bsdf_fraction, pdf, q_);
  } else {
    upload(*ctx_, pdf, batch.pdf);
  }
}

}  // namespace clr::radiosity
