#pragma once
// The path tracer's row of a sweep: one progressive render of the reference path tracer, extended pass by pass,
// each pass with its own seed so that the passes are independent and their spp-weighted mean is the image of all
// their samples. Its points: a timed pass of one sample, passes that double the samples up to half the first
// budget, one point at each time budget (the spp of the pass that ends there chosen from the rate measured so far,
// refined by further passes until within 5 % of it; the time measured), then passes that double the samples until
// the image's MAPE reaches the best trained model's, or the next would pass a time cap. Every point is a row of
// results.csv and an EXR under SWEEP_DIR/path_tracing, from which a rerun continues.
#include <filesystem>
#include <functional>
#include <vector>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "reference/path_tracer.hpp"
#include "sweep/results_csv.hpp"

namespace clr::sweep {

struct PathTracingPlan {
  reference::RenderOptions render;      // size and max depth; spp and seed are the chain's
  std::vector<double> budgets_minutes;  // equal-time points
  double target_mape = 0;               // doubling stops at or below it ...
  double cap_seconds = 0;               // ... or before a pass expected to end past this much rendering time
};

// Adds the path tracer's missing points to `rows`, calling `save` after each, until the plan is met or a stop is
// requested (Ctrl-C). Writes the images under `sweep_dir`/path_tracing.
void extend_path_tracing(const geometry::Geometry& geometry, const image::Image& reference,
                         const std::filesystem::path& sweep_dir, const PathTracingPlan& plan, std::vector<Row>& rows,
                         const std::function<void()>& save);

// The path tracer's time to an image of MAPE `mape`, from its points in `rows`: interpolated log–log between the
// two measured points around it, else (beyond the last point, or below the first) extrapolated from the nearest
// point with MAPE ∝ time^-1/2, the Monte Carlo rate — an estimate that ignores the reference's own noise floor.
struct TimeToError {
  double seconds = kNone;
  bool extrapolated = false;
};
TimeToError path_tracing_time_to(const std::vector<Row>& rows, double mape);

}  // namespace clr::sweep
