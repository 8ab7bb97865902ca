#pragma once
// Neural Radiosity training (DESIGN.md §2, method `nr`): each step draws a TrainingBatch on the host, evaluates
// sg(L_α) at the incident hits on the device, forms the right-hand side, and takes an Adam step on the residual.
// A run lives in RUN_DIR: config.json (settings), log.csv (one row per log interval), model.clr (checkpoint).
#include <filesystem>
#include <memory>

#include "cl/context.hpp"
#include "nn/loss.hpp"
#include "nn/network.hpp"
#include "radiosity/train_config.hpp"
#include "radiosity/training_batch.hpp"

namespace clr::radiosity {

// The N-Module for a scene: the paper's architecture with the device's width (default_width), the scene's
// bounding box, inputs the scene needs (albedo only when it varies), and the user's `network` overrides on top.
nn::NetworkConfig radiance_network_config(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                                          const TrainConfig& config, const cl::DeviceInfo& device);

struct StepStats {
  double loss = 0;          // mean residual loss over the batch
  std::size_t lookups = 0;  // incident samples that needed the network
  std::uint32_t non_finite = 0;
};

class Trainer {
 public:
  // Starts a new run in `run_dir` (which must be empty or absent), or continues one when `resume` is set:
  // then the run's config.json and model.clr are read back, and `config` only supplies the stopping rule.
  Trainer(cl::Context& ctx, const geometry::Geometry& geometry, TrainConfig config, std::filesystem::path run_dir,
          bool resume);

  // Trains until the step or time budget is spent or a stop signal arrives; checkpoints at the end.
  void run();
  StepStats step();
  void save_checkpoint() const;

  std::uint64_t steps_done() const { return network_->steps(); }
  const TrainConfig& config() const { return config_; }
  nn::Network& network() { return *network_; }

 private:
  void append_log(const std::string& line) const;

  cl::Context* ctx_;
  const geometry::Geometry* geometry_;
  geometry::SurfaceSampler sampler_;
  TrainConfig config_;
  std::filesystem::path run_dir_;
  std::unique_ptr<nn::Network> network_;
  nn::Loss loss_;
  float residual_power_ = 1;  // TrainConfig::relative_power, updated by run() as the budget is spent
  BatchSettings batch_settings_;
  TrainingBatch batch_;
  nn::NetworkContext train_ctx_;
  cl::Buffer<float> point_rows_, incident_rows_, weight_, emitted_, incident_radiance_, rhs_, d_output_;
  cl::Buffer<int> lookup_;
  cl::Buffer<std::uint32_t> non_finite_;
  cl::Kernel rhs_kernel_;
  double seconds_before_ = 0;  // training time of earlier sessions of a resumed run
};

// The default batch for a device: GPUs take the paper-sized batch, CPU devices a smaller one so a step stays
// interactive (the step cost is dominated by the MLP's GEMMs, DESIGN.md §6).
int default_batch(const cl::DeviceInfo& device);

// The N-Module's hidden width for a device: the paper's 512 on GPUs; 256 on CPU devices, where the 512-wide GEMMs
// are ~80 % of a step. Width 256 takes 3.2× the steps per unit of time, and at minutes-long budgets the error is
// the Monte Carlo noise of rare emitter hits, which more steps average down (the hash grid carries the detail):
// on a 2-core CPU the shared Cornell box reached MAPE 0.069–0.084 in 10 minutes (three seeds) against 0.099–0.109
// at 512, and both Veach scenes improved as much. README: "Training time against accuracy".
std::size_t default_width(const cl::DeviceInfo& device);

}  // namespace clr::radiosity
