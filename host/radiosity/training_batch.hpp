#pragma once
// The host half of one training step (DESIGN.md §2): M points (x, ω_o) drawn uniformly by area and direction on
// the surfaces the network models, N incident directions each from the BSDF, traced through delta chains to the
// next modelled surface. What the device needs comes out as flat arrays; the network is evaluated only on the
// `incident` rows (compacted), never on rays that escaped or died.
#include <cstdint>
#include <vector>

#include "geometry/surface_sampler.hpp"
#include "radiosity/surface_query.hpp"

namespace clr::radiosity {

struct TrainingBatch {
  std::size_t points = 0, samples = 0;
  std::vector<float> point_rows;     // points × kRawInputs: where L_α is trained
  std::vector<float> incident_rows;  // lookups × kRawInputs: where sg(L_α) is read
  std::vector<float> weight;         // points·samples × 3: f·cos/p times the delta chain's throughput
  std::vector<float> emitted;        // points·samples × 3: f·cos/p times the emission met along the chain
  std::vector<int> lookup;           // points·samples: row in incident_rows, or −1

  std::size_t lookups() const { return incident_rows.size() / nn::kRawInputs; }
};

struct BatchSettings {
  std::size_t points = 4096;
  std::size_t samples = 4;
  int max_delta_bounces = 8;
};

// Fills `batch` for training step `step` of a run seeded with `seed`; sample streams depend only on
// (seed, step, point index), so a batch is reproducible whatever the thread count.
void build_training_batch(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                          const BatchSettings& settings, std::uint64_t seed, std::uint64_t step, TrainingBatch& batch);

}  // namespace clr::radiosity
