#include "radiosity/residual.hpp"

#include <cmath>

#include "cl/buffer.hpp"

namespace clr::radiosity {

ResidualStats measure_residual(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network,
                               std::size_t points, std::size_t samples, std::uint64_t seed) {
  const geometry::SurfaceSampler sampler(geometry.scene());
  // Chunks of points bound the host and device memory whatever P·S is.
  const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(points, (1u << 18) / samples));
  auto rhs_kernel = ctx.program({"radiosity.cl"}).kernel("incident_rhs");
  cl::Buffer<std::uint32_t> non_finite(ctx, 1);
  non_finite.fill(0u);
  TrainingBatch batch;
  double sum = 0, sum_sq = 0;
  std::size_t done = 0;
  for (std::uint64_t c = 0; done < points; ++c) {
    const BatchSettings settings{std::min(chunk, points - done), samples, 8};
    // A stream of its own (step index past any training run's), so the metric never reuses training samples.
    build_training_batch(geometry, sampler, settings, seed, (1ull << 62) + c, batch);
    const std::size_t M = batch.points, K = batch.lookups();
    cl::Buffer<float> point_rows(ctx, std::span<const float>(batch.point_rows));
    cl::Buffer<float> incident_rows(ctx, std::span<const float>(batch.incident_rows));
    cl::Buffer<float> weight(ctx, std::span<const float>(batch.weight)),
        emitted(ctx, std::span<const float>(batch.emitted)), pdf(ctx, std::span<const float>(batch.pdf));
    cl::Buffer<int> lookup(ctx, std::span<const int>(batch.lookup));
    cl::Buffer<float> incident(ctx, std::max<std::size_t>(1, K) * 3), rhs(ctx, M * 3), pred(ctx, M * 3);
    if (K) network.infer(incident_rows, K, incident);
    rhs_kernel.args(weight, emitted, pdf, lookup, incident, unsigned(M), unsigned(samples), rhs, non_finite).launch(M);
    network.infer(point_rows, M, pred);
    const auto p = pred.read(), r = rhs.read();
    for (std::size_t m = 0; m < M; ++m) {
      double r2 = 0;
      for (int ch = 0; ch < 3; ++ch) r2 += std::pow(double(p[3 * m + ch]) - r[3 * m + ch], 2) / 3.0;
      sum += r2;
      sum_sq += r2 * r2;
    }
    done += M;
  }
  ResidualStats s;
  s.points = done;
  s.mean = sum / double(done);
  const double var = std::max(0.0, sum_sq / double(done) - s.mean * s.mean);
  s.standard_error = std::sqrt(var / double(std::max<std::size_t>(1, done - 1)));
  return s;
}

}  // namespace clr::radiosity
