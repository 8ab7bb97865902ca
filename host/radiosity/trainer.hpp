#pragma once
// Neural Radiosity training (docs/design.md §2). Each step draws a TrainingBatch on the host, evaluates sg(L_α) at the
// incident hits on the device, forms the right-hand side, and takes an Adam step on the residual. With method
// `isnr` the I-Module gives 8 vMF lobes per point first, a share of the incident directions is drawn from them
// on the device, and after the N-Module's step the I-Module takes its own on the KL / IKL gradient (sg both ways).
// A run lives in RUN_DIR (run_directory.hpp), which the trainer holds locked while it lives.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "cl/async.hpp"
#include "cl/context.hpp"
#include "distributed/gradient_exchange.hpp"
#include "nn/loss.hpp"
#include "nn/network.hpp"
#include "radiosity/guide/incident_sampling.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/train_config.hpp"
#include "radiosity/training_batch.hpp"

namespace clr::radiosity {

// The N-Module for a scene: the paper's architecture with the device's width (default_width), the scene's
// bounding box, inputs the scene needs (albedo only when it varies), and the user's `network` overrides on top.
nn::NetworkConfig radiance_network_config(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                                          const TrainConfig& config, const cl::DeviceInfo& device);

// How a step's host and device stages follow each other (docs/design.md §2). Serial: the host builds step k's
// batch, then the device runs its network math, uploads blocking. Pipelined: once step k's device work is enqueued
// (and flushed), the host prepares step k+1's batch as far as it does not depend on the networks — its points, and
// where nothing is guided its traced incident half — while the device computes; uploads are non-blocking writes
// from pinned memory. Both give the same parameters bit for bit: every random stream is keyed by (seed, step, use,
// index), and a batch prepared ahead is used only if the step and its settings are still the ones it was drawn for.
enum class StepSchedule { Serial, Pipelined };
// "serial" | "pipelined"; anything else throws InputError.
StepSchedule parse_step_schedule(const std::string& text);
// CLRADIOSITY_STEP_SCHEDULE when set, else pipelined.
StepSchedule default_schedule();

struct StepStats {
  double loss = 0;          // mean residual loss over the batch
  std::size_t lookups = 0;  // incident samples that needed the network
  std::uint32_t non_finite = 0;
  std::size_t guided = 0;  // incident samples drawn from the I-Module's mixture
};

class Trainer {
 public:
  // Starts a new run in `run_dir` (which must be empty or absent), or continues one when `resume` is set:
  // then the run's config.json and model.clr are read back, and `config` only supplies the stopping rule. Another
  // process training in `run_dir` is an InputError.
  // With several `ranks` (MPI, docs/mpi.md) each draws its share of the global batch, gradients are summed over
  // them before every Adam step, and rank 0 alone reads and writes RUN_DIR: the others take its config and state.
  Trainer(cl::Context& ctx, const geometry::Geometry& geometry, TrainConfig config, std::filesystem::path run_dir,
          bool resume, const distributed::Communicator& ranks = distributed::Communicator::single());

  // What run() may do beyond the plain training of `train` (the sweep: one run per configuration, snapshots at
  // every time budget on the way).
  struct RunOptions {
    // The time budget (config.minutes) counts the training time of earlier sessions of a resumed run too, and so
    // does the learning-rate schedule: a sweep's budgets are points of one run's total training time, however
    // many sessions it took. Off (`train --minutes`): the budget is this session's.
    bool minutes_in_total = false;
    // Called after every step with the run's training seconds so far (earlier sessions included). The time spent
    // in it does not count as training time, so writing a snapshot from it costs the run nothing.
    std::function<void(double seconds)> after_step;
    // Called at every `evaluate_every`-th step and at the run's last step (not after a stop signal); its figures
    // go into that step's log.csv row, which is logged whatever log_every says (convergence.hpp: train
    // --reference); nullopt (an evaluation that failed) leaves the row's columns empty. Its time, like
    // after_step's, is not training time. Should either throw, the run's checkpoint is written before the
    // exception leaves run(): what a side output does cannot cost the steps trained.
    long evaluate_every = 0;
    std::function<std::optional<image::Metrics>()> evaluate;
  };
  // Trains until the step or time budget is spent or a stop signal arrives; checkpoints at the end.
  void run(const RunOptions& options);
  void run() { run(RunOptions{}); }
  StepStats step();
  void set_schedule(StepSchedule schedule);
  // Adds the host's stage times of every later step to *times (null: stops timing; benchmarks only).
  void time_host_stages(HostStageTimes* times) { batch_.times = next_batch_.times = times; }
  StepSchedule schedule() const { return schedule_; }
  // Steps whose batch was prepared during the step before (pipelined) and used.
  std::uint64_t steps_prepared_ahead() const { return steps_prepared_ahead_; }
  void save_checkpoint() const;
  // The networks as they are now, as a run directory of their own (model.clr + config.json) that render, residual
  // and guide read: a sweep's snapshot of the run at one budget.
  void save_snapshot(const std::filesystem::path& dir) const;
  // Training seconds over every session of the run so far (as log.csv's `seconds` column counts them).
  double seconds_trained() const { return seconds_before_ + seconds_this_session_; }

  std::uint64_t steps_done() const { return network_->steps(); }
  // The figures of the step run() took last (what a caller's after_step reports).
  const StepStats& last_step() const { return last_step_; }
  const TrainConfig& config() const { return config_; }
  nn::Network& network() { return *network_; }
  nn::Network* guide() { return guide_.get(); }  // null for method nr
  const distributed::GradientExchange& exchange() const { return exchange_; }
  // Holds the N-Module fixed: steps train the I-Module alone, on the radiance the N-Module has (the guide's
  // variance study on a converged radiance field). Step streams then follow the I-Module's step count.
  void hold_radiance(bool hold) { hold_radiance_ = hold; }

 private:
  bool writes_run_dir() const { return run_.has_value(); }
  // trainer_ranks.cpp: ranks other than 0 take rank 0's config and state; all check they still agree, every
  // kRankCheckEvery steps (a checksum of the parameters: a few milliseconds against minutes of steps).
  static constexpr long kRankCheckEvery = 200;
  void share_rank0_state();
  void check_ranks_agree(std::uint64_t step) const;
  // The host's stages of `step` that can run while the device computes the step before: its points, and its traced
  // incident half where no direction is guided (method nr, or isnr with c = 1 throughout) or where the guided
  // directions were drawn ahead (the lagged guide).
  void prepare_ahead(std::uint64_t step);
  bool lagged() const { return guide_ && config_.guide_lag == 1; }
  // Whether the run goes on after `step` (a step budget ends it); a time budget is not known ahead.
  bool continues_after(std::uint64_t step) const {
    return config_.steps <= 0 || step + 1 < std::uint64_t(config_.steps);
  }
  // c for a step not yet begun, where the budget is in steps alone (it follows from the step); else the current c.
  BatchSettings settings_for(std::uint64_t step) const;
  // The lagged guide's device work early in `step`: the lobes its directions come from where none were drawn
  // ahead, then step + 1's lobes and directions (read back without blocking).
  void draw_lagged_lobes(std::uint64_t step);
  // Step `step`'s points into batch_: those the lag drew ahead for it into next_batch_, else drawn now.
  void take_points(std::uint64_t step, const BatchSettings& settings);
  // Step `step`'s points into next_batch_, unless they are there already.
  void draw_next_points(std::uint64_t step, const BatchSettings& settings);
  // A batch's point rows to the device (through pinned memory without blocking in the pipelined schedule), timed
  // as its upload stage.
  void upload_rows(const TrainingBatch& batch, cl::PinnedUpload<float>& pinned, cl::Buffer<float>& rows);

  cl::Context* ctx_;
  const geometry::Geometry* geometry_;
  StepStats last_step_;
  geometry::SurfaceSampler sampler_;
  TrainConfig config_;
  std::optional<RunDirectory> run_;  // rank 0's; the other ranks write nothing
  std::unique_ptr<nn::Network> network_;
  nn::Loss loss_;
  float residual_power_ = 1;  // TrainConfig::relative_power, updated by run() as the budget is spent
  BatchSettings batch_settings_;
  TrainingBatch batch_;
  nn::NetworkContext train_ctx_;
  IncidentSampling incident_;
  cl::Buffer<float> point_rows_, incident_radiance_, rhs_, d_output_;
  cl::Buffer<std::uint32_t> non_finite_;
  cl::Kernel rhs_kernel_;
  StepSchedule schedule_ = StepSchedule::Serial;
  // The batch in batch_ was prepared ahead for this step with these settings (incident half included if traced).
  struct Prepared {
    std::uint64_t step;
    BatchSettings settings;
    bool traced;
  };
  std::optional<Prepared> prepared_;
  std::uint64_t steps_prepared_ahead_ = 0;
  cl::PinnedUpload<float> point_rows_up_;
  // The I-Module (method isnr only).
  std::unique_ptr<nn::Network> guide_;
  nn::NetworkContext guide_ctx_;
  cl::Buffer<float> d_lobes_;
  // The lagged guide (config_.guide_lag = 1): the next step's points, drawn a step early so its lobes can be;
  // their row buffer and the I-Module's raw outputs there.
  TrainingBatch next_batch_;
  std::optional<std::uint64_t> next_points_;  // the step next_batch_'s points are for
  cl::Buffer<float> next_rows_, next_raw_, sampling_raw_;
  cl::PinnedUpload<float> next_rows_up_;
  // The I-Module before its last update, whose lobes drew this step's directions (checkpointed as guide_before.*,
  // so a resumed run draws exactly what an uninterrupted one would), and the step whose update followed the copy.
  std::unique_ptr<nn::Network> guide_before_;
  std::optional<std::uint64_t> before_step_;
  bool hold_radiance_ = false;
  cl::Buffer<float> point_radiance_;  // sg(L_α) at the points, where no forward computed it (held N-Module)
  double seconds_before_ = 0;         // training time of earlier sessions of a resumed run
  double seconds_this_session_ = 0;   // run()'s training time, updated every step
  distributed::GradientExchange exchange_;
};

// The default batch for a device: GPUs take the paper-sized batch, CPU devices a smaller one so a step stays
// interactive (the step cost is dominated by the MLP's GEMMs, docs/design.md §6).
int default_batch(const cl::DeviceInfo& device);

// The N-Module's hidden width for a device: the paper's 512 on GPUs; 256 on CPU devices, where the 512-wide GEMMs
// dominate a step. At minutes-long budgets the error is the Monte Carlo noise of rare emitter hits, which more
// steps average down (the hash grid carries the detail), so the narrower network's extra steps win on a CPU
// (docs/method.md; figures in docs/results/nr-training.md).
std::size_t default_width(const cl::DeviceInfo& device);

}  // namespace clr::radiosity
