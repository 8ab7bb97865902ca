#pragma once
// The paper's residual metric (ISNR Table 3): the mean squared rendering-equation residual
// r = L_α(x, ω_o) − (1/S) Σ f·cos·(Le + L_α(x', −ω_i))/p̃ over P random (x, ω_o), S samples each, averaged over
// RGB, with the standard error of that mean. With finite S the estimate includes the variance of the S-sample
// integral (E[r̂²] = r² + Var/S), as the paper's does. The samples come from the BSDF, or — given an I-Module —
// from the one-sample mixture training uses, so that the variance of one sample's estimate of the right-hand side
// (`rhs_variance`) shows what the guide does for the estimator with the N-Module held fixed.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "nn/network.hpp"
#include "radiosity/training_batch.hpp"

namespace clr::radiosity {

struct ResidualStats {
  double mean = 0;
  double standard_error = 0;
  double rhs_variance = 0;  // mean over points and RGB of the variance of a one-sample RHS estimate
  std::size_t points = 0;
  // The same means over the points on each of the scene's materials (Scene::materials' order; points 0 where the
  // surface sampler put none): where a sampling strategy gains or loses.
  struct Part {
    std::size_t points = 0;
    double mean = 0, rhs_variance = 0;
  };
  std::vector<Part> by_material;
};

// One point's S-sample estimate of the right-hand side: the model's prediction, the mean of the per-sample terms
// and their sample variance, per RGB channel.
struct RhsPoint {
  std::array<double, 3> prediction, mean, variance;
  std::uint32_t material = 0;  // index into Scene::materials
};

// Visits P random (x, ω_o) points' estimates, in chunks that bound memory whatever P·S is. Points depend only on
// (seed, index): the same points under either sampling. `guide` null: BSDF sampling; else the mixture with BSDF
// share `bsdf_fraction`.
// `next_event`: with the light samples of training's next-event estimation (TrainConfig::nee) beside the directions.
void estimate_rhs(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network, std::size_t points,
                  std::size_t samples, std::uint64_t seed, nn::Network* guide, float bsdf_fraction, bool next_event,
                  const std::function<void(const RhsPoint&)>& visit);

// `guide` null: BSDF sampling; else the mixture with BSDF share `bsdf_fraction`.
ResidualStats measure_residual(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network,
                               std::size_t points, std::size_t samples, std::uint64_t seed,
                               nn::Network* guide = nullptr, float bsdf_fraction = 1.0f, bool next_event = false);

}  // namespace clr::radiosity
