#pragma once
// `clradiosity sweep`: training time against accuracy for several methods, sample counts and seeds, beside the
// path tracer (docs/sweeps.md). Each configuration trains once, for the largest budget, and leaves a snapshot at
// every budget on the way; each snapshot is rendered and measured into a row of SWEEP_DIR/results.csv. A stop
// request (Ctrl-C) ends the sweep at the next safe point with every finished row kept; running it again
// continues: finished rows are skipped, an interrupted training resumes from its checkpoint.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "radiosity/train_config.hpp"

namespace clr::sweep {

struct SweepOptions {
  std::filesystem::path scene, dir;
  std::map<std::string, std::string> scene_parameters;  // -D key=value
  int sensor = 0;                                       // --sensor: the view every image is taken from
  std::filesystem::path reference;                      // empty: path-trace one into SWEEP_DIR/reference.exr
  std::vector<double> minutes;                          // the time budgets, in training minutes
  std::vector<std::string> methods;
  std::vector<int> samples;
  int seeds = 1;
  int width = 0, height = 0;  // 0: the scene's film
  int render_spp = 16;
  int reference_spp = 1024;
  std::size_t residual_points = 8192, residual_samples = 64;
  radiosity::TrainConfig base;  // --config: batch, network, … for every run
  // The path tracer's chain stops doubling at this multiple of the largest budget: a trained model far better than
  // path tracing at equal time would otherwise keep it rendering for hours; beyond, its time is extrapolated.
  double path_tracing_cap = 4;
  std::filesystem::path plot_script;  // bench/plot_sweep.py; empty: no figures
};

// InputError naming the option or file at fault before any work starts.
void run_sweep(cl::Context& ctx, const SweepOptions& options);

}  // namespace clr::sweep
