#pragma once
// Every training setting, with the paper's defaults (ISNR §4.3: Adam at 5e-3, N = 4, 8 vMF lobes). Read from
// `--config FILE.json`, overridden by CLI flags, validated, and saved as RUN_DIR/config.json so a run can be
// resumed and rendered with exactly the settings it was trained with.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace clr::radiosity {

struct TrainConfig {
  std::string method = "nr";          // "nr" (vanilla Neural Radiosity) or "isnr"
  std::string is_loss = "ikl";        // I-Module loss for isnr: "ikl" or "kl"
  std::string residual = "relative";  // "relative": r²/(sg(L)²+0.01); "l2": r² (paper Eq. 10)
  int samples = 4;                    // N incident directions per point
  int batch = 0;                      // M points per step; 0 = chosen for the device
  long steps = 0;                     // stop after this many steps (0 = no step limit)
  double minutes = 0;                 // stop after this much wall time (0 = no time limit)
  std::uint64_t seed = 1;
  double learning_rate = 5e-3;
  double lr_decay = 1.0;  // multiply the learning rate by this every lr_decay_steps
  long lr_decay_steps = 1000;
  double bsdf_fraction = 0.5;  // c in p̃ = c·p_bsdf + (1−c)·q (isnr)
  long log_every = 25;         // rows of log.csv
  long checkpoint_every = 500;
  nlohmann::json network = nlohmann::json::object();  // encoding and MLP settings, passed to the network engine

  // Throws InputError naming the first impossible setting (e.g. "samples must be ≥ 1, got 0").
  void validate() const;
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TrainConfig, method, is_loss, residual, samples, batch, steps, minutes,
                                                seed, learning_rate, lr_decay, lr_decay_steps, bsdf_fraction, log_every,
                                                checkpoint_every, network)

// Applies the keys of `j` over `base`. An unknown key or a value of the wrong type is an InputError naming the
// key (a misspelt key must not be silently ignored); the result is validated.
TrainConfig parse_train_config(const nlohmann::json& j, const TrainConfig& base = {});

TrainConfig load_train_config(const std::string& path);

}  // namespace clr::radiosity
