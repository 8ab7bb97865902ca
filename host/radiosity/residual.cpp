#include "radiosity/residual.hpp"

#include <cmath>

#include "cl/buffer.hpp"
#include "radiosity/guide/incident_sampling.hpp"

namespace clr::radiosity {

void estimate_rhs(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network, std::size_t points,
                  std::size_t samples, std::uint64_t seed, nn::Network* guide, float bsdf_fraction, bool next_event,
                  const std::function<void(const RhsPoint&)>& visit) {
  const geometry::SurfaceSampler sampler(geometry.scene());
  const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(points, (1u << 18) / samples));
  IncidentSampling incident(ctx);
  TrainingBatch batch;
  std::size_t done = 0;
  for (std::uint64_t c = 0; done < points; ++c) {
    BatchSettings settings{std::min(chunk, points - done), samples,          8,
                           guide ? bsdf_fraction : 1.0f,   guide != nullptr, next_event};
    // A stream of its own (step index past any training run's), so the metric never reuses training samples.
    const std::uint64_t step = (1ull << 62) + c;
    sample_training_points(sampler, geometry.scene(), settings, seed, step, batch);
    const std::size_t M = batch.points;
    cl::Buffer<float> point_rows(ctx, std::span<const float>(batch.point_rows)), lobes;
    if (guide) {
      lobes = cl::Buffer<float>(ctx, M * kVmfRaw);
      guide->infer(point_rows, M, lobes);
    }
    incident.sample(geometry, settings, seed, step, guide ? &lobes : nullptr, batch);
    const std::size_t K = batch.lookups();
    cl::Buffer<float> radiance(ctx, std::max<std::size_t>(1, K) * 3), pred(ctx, M * 3);
    if (K) network.infer(incident.incident_rows, K, radiance);
    network.infer(point_rows, M, pred);
    const auto L = radiance.read(), p = pred.read();
    const auto pdf = incident.pdf.read();
    for (std::size_t m = 0; m < M; ++m) {
      RhsPoint point;
      point.material = batch.surface[m].material;
      for (std::size_t ch = 0; ch < 3; ++ch) {
        // A sample's term with its light sample (whose mean is in `direct`), so that their variance counts too.
        double s1 = 0, s2 = 0, light = 0;
        for (std::size_t n = 0; n < samples; ++n) {
          const std::size_t s = m * samples + n;
          double term = batch.emitted[3 * s + ch];
          if (batch.lookup[s] >= 0) term += double(batch.weight[3 * s + ch]) * L[3 * std::size_t(batch.lookup[s]) + ch];
          term /= pdf[s];
          if (!batch.light.empty()) {
            light += batch.light[3 * s + ch];
            term += batch.light[3 * s + ch];
          }
          if (!std::isfinite(term)) continue;
          s1 += term;
          s2 += term * term;
        }
        point.prediction[ch] = p[3 * m + ch];
        // Delta lights' next-event term: a constant per point, so it adds to the mean and not to the variance.
        const double delta = batch.direct.empty() ? 0.0 : batch.direct[3 * m + ch] - light / double(samples);
        point.mean[ch] = s1 / double(samples) + delta;
        point.variance[ch] =
            samples > 1 ? std::max(0.0, s2 - double(samples) * point.mean[ch] * point.mean[ch]) / double(samples - 1)
                        : 0.0;
      }
      visit(point);
    }
    done += M;
  }
}

ResidualStats measure_residual(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& network,
                               std::size_t points, std::size_t samples, std::uint64_t seed, nn::Network* guide,
                               float bsdf_fraction, bool next_event) {
  double sum = 0, sum_sq = 0, variance = 0;
  std::size_t done = 0;
  ResidualStats s;
  s.by_material.resize(geometry.scene().materials.size());
  estimate_rhs(ctx, geometry, network, points, samples, seed, guide, bsdf_fraction, next_event, [&](const RhsPoint& p) {
    double r2 = 0, v = 0;
    for (std::size_t ch = 0; ch < 3; ++ch) {
      r2 += std::pow(p.prediction[ch] - p.mean[ch], 2) / 3.0;
      v += p.variance[ch] / 3.0;
    }
    sum += r2;
    sum_sq += r2 * r2;
    variance += v;
    ++done;
    auto& part = s.by_material.at(p.material);
    part.mean += r2;
    part.rhs_variance += v;
    ++part.points;
  });
  for (auto& part : s.by_material)
    if (part.points) {
      part.mean /= double(part.points);
      part.rhs_variance /= double(part.points);
    }
  s.points = done;
  s.mean = sum / double(done);
  s.rhs_variance = variance / double(done);
  const double var = std::max(0.0, sum_sq / double(done) - s.mean * s.mean);
  s.standard_error = std::sqrt(var / double(std::max<std::size_t>(1, done - 1)));
  return s;
}

}  // namespace clr::radiosity
