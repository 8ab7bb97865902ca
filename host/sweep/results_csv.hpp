#pragma once
// SWEEP_DIR/results.csv: one row per trained configuration × point (a time budget, or the step count of an ISNR
// row for the equal-steps comparison) and one per point of the path tracer's progressive render. The file is
// rewritten whole under a temporary name and renamed for every new row, so an interrupted sweep leaves only
// complete rows, and a rerun keeps them and skips their work.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace clr::sweep {

inline constexpr double kNone = std::numeric_limits<double>::quiet_NaN();  // an empty cell

// What made a row: a trained model's snapshot, or the path tracer.
enum class RowKind { Model, PathTracing };
// What the row measures: Budget (at `budget_minutes` of training or, for the path tracer, of rendering), Steps (a
// model at `steps`, the step count an ISNR run reached at a budget) or Progress (a path tracer point taken on the
// way to a model's error).
enum class Point { Budget, Steps, Progress };
// Their names in results.csv: model, path_tracing; budget, steps, progress.
const char* to_string(RowKind kind);
const char* to_string(Point point);

struct Row {
  RowKind kind = RowKind::Model;
  std::string method;  // nr, isnr-kl, isnr-ikl; "pt" for the path tracer
  int samples = 0;     // N incident directions per point (models)
  std::uint64_t seed = 0;
  Point point = Point::Budget;
  double budget_minutes = kNone;
  std::uint64_t steps = 0;  // training steps (models)
  double seconds = 0;       // training seconds (models), rendering seconds so far (path tracer)
  double peak_device_mib = kNone;
  int spp = 0;                // samples per pixel of the image measured
  double render_seconds = 0;  // the model's render at `spp` (the path tracer: its whole time, = seconds)
  double mape = kNone, mse = kNone, relmse = kNone;
  std::uint64_t non_finite = 0;
  double residual = kNone, residual_se = kNone;  // the rendering-equation residual metric (models)
  std::string image, error_map;                  // PNGs, relative to SWEEP_DIR
  // Incident samples (points × N) the model had trained on: steps × batch × N, for comparing configurations at
  // equal samples. 0 where unknown: the path tracer, and rows of a results.csv written before the column.
  std::uint64_t incident_samples = 0;

  // What identifies a row across runs of the sweep: a rerun skips the work of every key present.
  std::string key() const;
};

// The rows of `path`, in file order; none when it does not exist. InputError naming file:line on a malformed row.
std::vector<Row> read_results(const std::filesystem::path& path);
void write_results(const std::filesystem::path& path, const std::vector<Row>& rows);

}  // namespace clr::sweep
