#pragma once
// One training session as `train` runs it (docs/cli.md), shared by the CLI and the Python module
// (python/module.cpp): the scene loaded and checked, the settings assembled (config file, preset, explicit
// settings over both), what watches the run (--reference evaluations, --preview) checked before any step, the
// device opened, the trainer run to its budget or a stop signal, the convergence figure drawn.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "radiosity/convergence.hpp"
#include "radiosity/train_config.hpp"

namespace clr::radiosity {

class Trainer;

// The most camera rays per pixel an evaluation takes (--eval-spp).
inline constexpr int kMaxEvaluationSpp = 1 << 16;

struct TrainRequest {
  std::string scene;                              // the scene file
  std::map<std::string, std::string> parameters;  // the scene's $parameters (-D)
  int sensor = 0;                                 // the sensor evaluations and previews render (--sensor)
  // The scene as loaded already (Python's Scene, whose path, parameters and sensor are the fields above): trained
  // as it is, not read again. Null: read from `scene`.
  const scene::Scene* loaded = nullptr;
  std::string run_dir, device, preset, config_file;
  nlohmann::json config;  // settings given inline, as a config file holds them (null: none)
  bool resume = false, other_scene = false;
  // Settings given explicitly (flags, keyword arguments): applied over the config file, and again over a preset;
  // they end with TrainConfig::validate().
  std::function<void(TrainConfig&)> settings;
  // Which of them were given, by the CLI's flag names ("--method", "--eval-spp", …): a resumed run refuses a flag
  // that contradicts its config, and defaults (evaluation spp, intervals) yield to what was given.
  std::function<bool(const char* flag)> given;
  EvaluationSettings evaluation;  // reference empty: no evaluations
  std::string preview;            // empty: no preview
  long preview_every = 0;
  // Called after every step on rank 0 (the run's training seconds so far); its time is not training time. It may
  // request_stop() (common/stop_signal.hpp) to end the run with a checkpoint.
  std::function<void(const Trainer& trainer, double seconds)> after_step;
};

struct TrainOutcome {
  bool rank_zero = true;  // the other ranks of an MPI job write nothing and report nothing
  std::filesystem::path model;
  std::uint64_t steps = 0;
  double peak_device_mib = 0;
  bool preview_written = false;
  std::optional<std::filesystem::path> convergence;  // the figure, where the log had rows to draw
  // Previews, evaluations and figures that failed (each reported on stderr as it happened); the training and its
  // checkpoint are whole regardless.
  std::size_t side_output_failures = 0;
};

// The settings `train` takes by flag, and where each lives in config.json (a JSON pointer). A resumed run refuses one
// that contradicts its config — all but the budget, which a resume may extend. The Python module's keyword arguments
// are these flags' names.
struct SettingFlag {
  const char* flag;
  const char* pointer;
  bool fixed_on_resume;
};
const std::vector<SettingFlag>& setting_flags();

// Trains as `request` says. InputError (before any step, and before RUN_DIR exists where the request itself is at
// fault) for bad input; informational lines on stderr unless Progress::silenced().
TrainOutcome train(const TrainRequest& request);

}  // namespace clr::radiosity
