#include "radiosity/training_batch.hpp"

#include <algorithm>

#include "common/parallel.hpp"

namespace clr::radiosity {
namespace {

// Distinct RNG streams for the two uses of one (seed, step): surface points, and the per-point direction streams.
std::uint64_t stream_id(std::uint64_t seed, std::uint64_t step, std::uint64_t use) {
  return (seed * 0x9E3779B97F4A7C15ull) ^ (step * 0xBF58476D1CE4E5B9ull) ^ (use * 0x94D049BB133111EBull);
}

}  // namespace

void build_training_batch(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                          const BatchSettings& settings, std::uint64_t seed, std::uint64_t step, TrainingBatch& batch) {
  const scene::Scene& scene = geometry.scene();
  const std::size_t M = settings.points, N = settings.samples, R = nn::kRawInputs;
  batch.points = M;
  batch.samples = N;
  batch.point_rows.resize(M * R);
  batch.weight.assign(M * N * 3, 0.0f);
  batch.emitted.assign(M * N * 3, 0.0f);
  batch.lookup.assign(M * N, -1);
  // Every sample's would-be lookup row, compacted afterwards in sample order (deterministic).
  std::vector<float> candidate(M * N * R);

  const auto points = sampler.sample(stream_id(seed, step, 0), M);
  parallel_for(M, 64, [&](std::size_t first, std::size_t last) {
    for (std::size_t m = first; m < last; ++m) {
      Pcg32 rng(m, stream_id(seed, step, 1));
      const auto& x = points[m];
      // ω_o uniform over the directions the surface can scatter into: the whole sphere for two-sided BSDFs,
      // the hemisphere above the shading normal for one-sided ones (their black side is never queried).
      const scene::BsdfPoint bsdf = x.point.bsdf(scene);
      Vec3 wo = scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
      if (!bsdf.bsdf->two_sided() && glm::dot(wo, x.point.frame.n) < 0.0f)
        wo -= 2.0f * glm::dot(wo, x.point.frame.n) * x.point.frame.n;
      write_raw_row(scene, x.point, wo, &batch.point_rows[m * R]);
      for (std::size_t n = 0; n < N; ++n) {
        const std::size_t s = m * N + n;
        const float u_lobe = rng.next_float();
        const auto bs = bsdf.sample(wo, u_lobe, {rng.next_float(), rng.next_float()});
        if (!bs) continue;
        const PathEnd path =
            trace_to_surface(geometry, {x.point.spawn_origin(bs->wi), 0.0f, bs->wi}, rng, settings.max_delta_bounces);
        for (int c = 0; c < 3; ++c) {
          batch.weight[3 * s + c] = bs->weight[c] * path.throughput[c];
          batch.emitted[3 * s + c] = bs->weight[c] * path.emitted[c];
        }
        if (path.at_surface) {
          write_raw_row(scene, path.point, path.wo, &candidate[s * R]);
          batch.lookup[s] = 0;  // marked; numbered below
        }
      }
    }
  });

  std::size_t rows = 0;
  for (std::size_t s = 0; s < M * N; ++s)
    if (batch.lookup[s] >= 0) batch.lookup[s] = int(rows++);
  batch.incident_rows.resize(rows * R);
  for (std::size_t s = 0; s < M * N; ++s)
    if (batch.lookup[s] >= 0) std::copy_n(&candidate[s * R], R, &batch.incident_rows[std::size_t(batch.lookup[s]) * R]);
}

}  // namespace clr::radiosity
