#pragma once
// One configuration of a sweep: its single training run with a snapshot at each of its points, and each snapshot
// rendered and measured into a row.
#include <filesystem>
#include <vector>

#include "cl/context.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "sweep/results_csv.hpp"
#include "sweep/sweep.hpp"
#include "sweep/sweep_plan.hpp"

namespace clr::sweep {

// What every configuration shares.
struct SweepContext {
  cl::Context& ctx;
  const geometry::Geometry& geometry;
  const image::Image& reference;
  const SweepOptions& options;  // its budgets sorted, each once
  std::vector<Row>& rows;       // results.csv's, kept in step with the file
  std::filesystem::path results;
};

// Adds the rows `config` lacks: evaluates snapshots already on disk, trains (fresh, or resumed from its
// checkpoint) to the largest budget taking the missing snapshots on the way, and evaluates those. Returns early,
// rows kept, on a stop request.
void run_configuration(const SweepContext& sweep, const Configuration& config);

}  // namespace clr::sweep
