#pragma once
// What a sweep trains: every method × N × seed once, with snapshots at every time budget on the way (one run per
// configuration, not one per budget; docs/sweeps.md).
#include <cstdint>
#include <string>
#include <vector>

#include "radiosity/train_config.hpp"

namespace clr::sweep {

// One trained configuration. Methods: "nr" (BSDF sampling only), "isnr-kl" and "isnr-ikl" (the I-Module trained on
// the KL or the Improved KL divergence): the paper's ablation names.
struct Configuration {
  std::string method;
  int samples = 4;
  std::uint64_t seed = 1;

  bool guided() const { return method != "nr"; }
  std::string name() const;  // "isnr-ikl-n4-seed1": its folder under SWEEP_DIR/runs
  // `base` (defaults or --config) with this configuration's method, N and seed, and a time budget of `minutes`
  // over the run's whole training time.
  radiosity::TrainConfig train_config(const radiosity::TrainConfig& base, double minutes) const;
};

// InputError naming the value unless it is nr, isnr-kl or isnr-ikl.
void check_method(const std::string& method);

// Every method × samples × seed, the guided methods first: NR's runs take an extra snapshot at each step count an
// ISNR run of the same N and seed reached at a budget (the equal-steps comparison), which needs those rows first.
std::vector<Configuration> plan_configurations(const std::vector<std::string>& methods, const std::vector<int>& samples,
                                               int seeds);

// A budget's folder name: "0.5min".
std::string budget_label(double minutes);

}  // namespace clr::sweep
