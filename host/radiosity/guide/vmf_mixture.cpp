#include "radiosity/guide/vmf_mixture.hpp"

#include "nn/gemm.hpp"
#include "nn/programs.hpp"

namespace clr::radiosity {

namespace {
constexpr std::size_t kLobeFields = 14;  // VMF_LOBE_FIELDS
}

VmfMixture::VmfMixture(cl::Context& ctx)
    : ctx_(&ctx),
      total_(ctx, 1),
      non_finite_(ctx, 1),
      decode_(ctx.program(nn::programs::vmf).kernel("vmf_decode")),
      sample_(ctx.program(nn::programs::vmf).kernel("vmf_sample")),
      pdf_(ctx.program(nn::programs::vmf).kernel("vmf_mixture_pdf")),
      dlogq_(ctx.program(nn::programs::vmf).kernel("vmf_dlogq")),
      loss_(ctx.program(nn::programs::vmf).kernel("guide_loss")) {
  total_.fill(0.0f);
  non_finite_.fill(0u);
}

void VmfMixture::decode(const cl::Buffer<float>& raw, const cl::Buffer<float>& normals, std::size_t points) {
  if (lobes_.size() < points * kVmfLobes * kLobeFields)
    lobes_ = cl::Buffer<float>(*ctx_, points * kVmfLobes * kLobeFields);
  points_ = points;
  decode_.args(raw, normals, nn::u32(points), lobes_).launch(points);
}

void VmfMixture::sample(const cl::Buffer<float>& u, std::size_t samples, cl::Buffer<float>& dirs) {
  sample_.args(lobes_, u, nn::u32(points_), nn::u32(samples), dirs).launch(points_ * samples);
}

void VmfMixture::mixture_pdf(const cl::Buffer<float>& dirs, const cl::Buffer<float>& bsdf_pdf, std::size_t samples,
                             float bsdf_fraction, cl::Buffer<float>& pdf, cl::Buffer<float>& q) {
  pdf_.args(lobes_, dirs, bsdf_pdf, nn::u32(points_), nn::u32(samples), bsdf_fraction, pdf, q)
      .launch(points_ * samples);
}

void VmfMixture::dlogq(const cl::Buffer<float>& dirs, std::size_t samples, cl::Buffer<float>& out) {
  dlogq_.args(lobes_, dirs, nn::u32(points_), nn::u32(samples), out).launch(points_ * samples);
}

// The loss kernel's group: a power of two (its tree sum needs one), 64 as the other reductions.
constexpr std::size_t kLossGroup = 64;

void VmfMixture::loss(const GuideSamples& s, std::size_t samples, bool improved, cl::Buffer<float>& d_raw,
                      std::size_t mean_over) {
  loss_
      .args(nn::u32(points_), nn::u32(samples), lobes_, s.dirs, s.bsdf_pdf, s.pdf, s.weight, s.emitted, s.lookup,
            s.radiance, s.scattered, s.scattered_scale, s.direct ? *s.direct : s.scattered, s.direct ? 1u : 0u,
            improved ? 1u : 0u, 1.0f / float(mean_over ? mean_over : points_), d_raw, total_, non_finite_,
            cl::LocalMemory{kLossGroup * sizeof(float)})
      .launch(points_, kLossGroup);
}

nn::LossValue VmfMixture::take() {
  nn::LossValue v{double(total_.read()[0]), non_finite_.read()[0]};
  total_.fill(0.0f);
  non_finite_.fill(0u);
  return v;
}

}  // namespace clr::radiosity
