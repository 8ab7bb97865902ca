#pragma once
// The paper's residual metric (ISNR Table 3): the mean squared rendering-equation residual
// r = L_α(x, ω_o) − (1/S) Σ f·cos·(Le + L_α(x', −ω_i))/p over P random (x, ω_o), S BSDF samples each,
// averaged over RGB, with the standard error of that mean. With finite S the estimate includes the variance of
// the S-sample integral (E[r̂²] = r² + Var/S), as the paper's does.
#include "nn/network.hpp"
#include "radiosity/training_batch.hpp"

namespace clr::radiosity {

struct ResidualStats {
  double mean = 0;
  double standard_error = 0;
  std::size_t points = 0;
};

ResidualStats measure_residual(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network,
                               std::size_t points, std::size_t samples, std::uint64_t seed);

}  // namespace clr::radiosity
