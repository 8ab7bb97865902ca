#include "sweep/configuration_run.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/stop_signal.hpp"
#include "radiosity/convergence.hpp"
#include "radiosity/residual.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"

namespace clr::sweep {
namespace fs = std::filesystem;
namespace {

// The residual's points are the same for every snapshot (a fixed seed), so rows differ by the model alone.
constexpr std::uint64_t kResidualSeed = 7;

// A point of the run to snapshot: a time budget, or (NR) the step count an ISNR run reached at a budget.
struct Target {
  Point point;  // Budget or Steps
  double minutes = kNone;
  std::uint64_t steps = 0;
  fs::path dir;  // its snapshot: model.clr, config.json, snapshot.json (written last: the snapshot is complete)

  bool reached(double seconds, std::uint64_t steps_done) const {
    return point == Point::Budget ? seconds >= minutes * 60.0 : steps_done >= steps;
  }
  bool taken() const { return fs::exists(dir / "snapshot.json"); }
};

Row base_row(const Configuration& config, const Target& t) {
  Row r;
  r.kind = RowKind::Model;
  r.method = config.method;
  r.samples = config.samples;
  r.seed = config.seed;
  r.point = t.point;
  r.budget_minutes = t.minutes;
  r.steps = t.steps;
  return r;
}

bool has_row(const std::vector<Row>& rows, const Row& row) {
  const std::string key = row.key();
  return std::any_of(rows.begin(), rows.end(), [&](const Row& r) { return r.key() == key; });
}

// A field of a snapshot record; InputError naming the file when it is missing or of another type (run files are
// input like any other).
template <typename T>
T record_field(const nlohmann::json& record, const char* key, const fs::path& file) {
  try {
    return record.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(file.string() + ": '" + key + "' is missing or not a number");
  }
}

// The steps of the run's snapshot at its largest budget, once it has one: the run is finished, and an equal-steps
// point beyond them is out of its reach (it trains no further for one).
std::optional<std::uint64_t> finished_steps(const fs::path& root, double max_minutes) {
  const fs::path file = root / budget_label(max_minutes) / "snapshot.json";
  if (!fs::exists(file)) return std::nullopt;
  return record_field<std::uint64_t>(read_json_file(file, "snapshot record"), "steps", file);
}

// The points of `config` without a row yet that its run can give.
std::vector<Target> missing_targets(const SweepContext& sweep, const Configuration& config, const fs::path& root) {
  std::vector<Target> targets;
  for (double minutes : sweep.options.minutes) {
    Target t{Point::Budget, minutes, 0, root / budget_label(minutes)};
    if (!has_row(sweep.rows, base_row(config, t))) targets.push_back(t);
  }
  if (config.guided()) return targets;
  const auto finished = finished_steps(root, sweep.options.minutes.back());
  for (const auto& r : sweep.rows)
    if (r.kind == RowKind::Model && r.point == Point::Budget && r.method != "nr" && r.samples == config.samples &&
        r.seed == config.seed && (!finished || r.steps <= *finished)) {
      Target t{Point::Steps, kNone, r.steps, root / ("steps" + std::to_string(r.steps))};
      const bool listed = std::any_of(targets.begin(), targets.end(),
                                      [&](const Target& o) { return o.point == Point::Steps && o.steps == r.steps; });
      if (!listed && !has_row(sweep.rows, base_row(config, t))) targets.push_back(t);
    }
  return targets;
}

void take_snapshot(const radiosity::Trainer& trainer, const cl::Context& ctx, const Target& t) {
  trainer.save_snapshot(t.dir);
  write_record_atomically(t.dir / "snapshot.json",
                          nlohmann::json{{"steps", trainer.steps_done()},
                                         {"seconds", trainer.seconds_trained()},
                                         {"peak_device_bytes", ctx.peak_bytes()}}
                                  .dump() +
                              "\n",
                          "snapshot record");
}

void evaluate(const SweepContext& sweep, const Configuration& config, const Target& t) {
  const fs::path record = t.dir / "snapshot.json";
  const auto info = read_json_file(record, "snapshot record");
  auto network = radiosity::RunDirectory::load_radiance(sweep.ctx, t.dir);
  const auto field = radiosity::radiance_query(sweep.ctx, *network);
  // A few pixels first, so that the timed render does not include building the device's programs (a resumed
  // sweep evaluates snapshots before any training has built them).
  radiosity::render(sweep.geometry, field, {.width = 4, .height = 4, .spp = 1});
  // The same measure as `train --reference`: a row equals the log.csv columns of a run evaluated the same way.
  const auto evaluation = radiosity::evaluate_model(sweep.geometry, field, sweep.reference, sweep.options.render_spp);
  const auto& img = evaluation.image;
  Row r = base_row(config, t);
  r.render_seconds = evaluation.render_seconds;
  r.steps = record_field<std::uint64_t>(info, "steps", record);  // a steps point's own count: the hook saw every step
  r.seconds = record_field<double>(info, "seconds", record);
  r.peak_device_mib = double(record_field<std::uint64_t>(info, "peak_device_bytes", record)) / double(1 << 20);
  r.incident_samples = radiosity::RunDirectory::load_config(t.dir).incident_samples(r.steps);  // its batch, resolved
  r.spp = sweep.options.render_spp;
  const auto& m = evaluation.metrics;
  r.mape = m.mape;
  r.mse = m.mse;
  r.relmse = m.relmse;
  r.non_finite = m.non_finite;
  const auto residual = radiosity::measure_residual(sweep.ctx, sweep.geometry, *network, sweep.options.residual_points,
                                                    sweep.options.residual_samples, kResidualSeed);
  r.residual = residual.mean;
  r.residual_se = residual.standard_error;
  const fs::path rel = fs::relative(t.dir, sweep.options.dir);
  r.image = (rel / "render.png").string();
  r.error_map = (rel / "error.png").string();
  image::write_png(sweep.options.dir / r.image, img);
  image::write_png(sweep.options.dir / r.error_map, image::error_map(img, sweep.reference));
  sweep.rows.push_back(r);
  write_results(sweep.results, sweep.rows);
  std::printf("sweep: %s at %s: %llu steps, %.1f s, MAPE %.4g, relMSE %.4g, residual %.4g, render %.3g s\n",
              config.name().c_str(),
              t.point == Point::Budget ? budget_label(t.minutes).c_str() : ("step " + std::to_string(t.steps)).c_str(),
              static_cast<unsigned long long>(r.steps), r.seconds, r.mape, r.relmse, r.residual, r.render_seconds);
}

}  // namespace

void run_configuration(const SweepContext& sweep, const Configuration& config) {
  const fs::path root = sweep.options.dir / "runs" / config.name(), train_dir = root / "train";
  auto targets = missing_targets(sweep, config, root);
  if (targets.empty()) {
    std::printf("sweep: %s: every row done, reused\n", config.name().c_str());
    return;
  }
  const auto evaluate_taken = [&] {
    for (const auto& t : targets)
      if (!stop_requested() && t.taken() && !has_row(sweep.rows, base_row(config, t))) evaluate(sweep, config, t);
  };
  evaluate_taken();
  std::vector<Target> pending;
  for (const auto& t : targets)
    if (!t.taken()) pending.push_back(t);
  // Only time budgets make the run train.
  const auto budget_pending = [&] {
    return std::any_of(pending.begin(), pending.end(), [](const Target& t) { return t.point == Point::Budget; });
  };
  if (!budget_pending() || stop_requested()) return;

  const double max_minutes = sweep.options.minutes.back();  // sorted
  const auto train_config = config.train_config(sweep.options.base, max_minutes);
  double first_pending_s = max_minutes * 60.0;
  for (const auto& t : pending)
    if (t.point == Point::Budget) first_pending_s = std::min(first_pending_s, t.minutes * 60.0);
  std::optional<radiosity::Trainer> trainer;
  if (fs::exists(radiosity::RunDirectory::model_path(train_dir))) {
    trainer.emplace(sweep.ctx, sweep.geometry, train_config, train_dir, true);
    // A run whose checkpoint is already past a budget without a snapshot (possible only after a kill without
    // Ctrl-C's checkpoint) cannot give that budget's model: it starts again.
    if (trainer->seconds_trained() > first_pending_s) {
      std::printf("sweep: %s: its checkpoint (%.1f s) is past a budget without a snapshot; training again\n",
                  config.name().c_str(), trainer->seconds_trained());
      trainer.reset();
    } else {
      std::printf("sweep: %s: resuming at %.1f s of training\n", config.name().c_str(), trainer->seconds_trained());
    }
  }
  if (!trainer) {
    fs::remove_all(train_dir);  // a run killed before its first checkpoint, or one past use
    trainer.emplace(sweep.ctx, sweep.geometry, train_config, train_dir, false);
  }
  // The peak from here on: the networks in memory and what their steps add, without the buffers of a device's
  // one-off timed probes (the first run's construction) or of an earlier configuration's renders.
  sweep.ctx.reset_peak();
  // The hook sees every step count from here on: an equal-steps point the run has passed is out of its reach.
  std::erase_if(pending, [&](const Target& t) { return t.point == Point::Steps && t.steps <= trainer->steps_done(); });
  radiosity::Trainer::RunOptions run;
  run.minutes_in_total = true;
  run.after_step = [&](double seconds) {
    for (auto it = pending.begin(); it != pending.end();)
      if (it->reached(seconds, trainer->steps_done())) {
        take_snapshot(*trainer, sweep.ctx, *it);
        it = pending.erase(it);
      } else {
        ++it;
      }
  };
  std::printf("sweep: %s: training to %s\n", config.name().c_str(), budget_label(max_minutes).c_str());
  std::fflush(stdout);
  trainer->run(run);
  // The run ends at the first step past the largest budget, after the hook's last look: that state is its model.
  if (!stop_requested())
    for (const auto& t : pending)
      if (t.point == Point::Budget) take_snapshot(*trainer, sweep.ctx, t);
  trainer.reset();  // its device memory, before rendering
  evaluate_taken();
}

}  // namespace clr::sweep
