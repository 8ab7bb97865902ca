#include "radiosity/trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cl/buffer.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "distributed/share.hpp"
#include "nn/checkpoint.hpp"
#include "nn/programs.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/radiance_scale.hpp"
#include "radiosity/scene_inputs.hpp"
#include "radiosity/trained_model.hpp"

namespace clr::radiosity {

namespace fs = std::filesystem;

StepSchedule parse_step_schedule(const std::string& text) {
  if (text == "serial") return StepSchedule::Serial;
  if (text == "pipelined") return StepSchedule::Pipelined;
  throw InputError("step schedule '" + text + "' is not one of serial, pipelined");
}

StepSchedule default_schedule() {
  if (const char* env = std::getenv("CLRADIOSITY_STEP_SCHEDULE"); env && *env) {
    try {
      return parse_step_schedule(env);
    } catch (const InputError& e) {
      throw InputError(std::string("CLRADIOSITY_STEP_SCHEDULE: ") + e.what());
    }
  }
  // Pipelined on every device: on GPUs it hides the host's stages; on PoCL, where host and device share the cores,
  // it was not slower than serial (docs/results/benchmarks.md), so one schedule serves both.
  return StepSchedule::Pipelined;
}

int default_batch(const cl::DeviceInfo& device) { return device.type == cl::DeviceType::Gpu ? 16384 : 4096; }

std::size_t default_width(const cl::DeviceInfo& device) { return device.type == cl::DeviceType::Gpu ? 512 : 256; }

nn::NetworkConfig radiance_network_config(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                                          const TrainConfig& config, const cl::DeviceInfo& device) {
  const SceneInputs in = scene_inputs(geometry, sampler);
  nn::NetworkConfig base = nn::n_module_config(in.lo, in.hi);
  base.width = default_width(device);
  base.encoder.albedo = in.albedo_varies;
  base.output_scale = radiance_scale(geometry.scene());
  base.seed = config.seed;
  const nn::NetworkConfig merged = nn::merge_patch(base, config.network);
  require_radiance_network(merged);
  return merged;
}

Trainer::Trainer(cl::Context& ctx, const geometry::Geometry& geometry, TrainConfig config, fs::path run_dir,
                 bool resume, const distributed::Communicator& ranks)
    : ctx_(&ctx),
      geometry_(&geometry),
      sampler_(geometry.scene()),
      config_(std::move(config)),
      loss_(ctx),
      incident_(ctx),
      non_finite_(ctx, 1),
      rhs_kernel_(ctx.program(nn::programs::radiosity).kernel("incident_rhs")),
      exchange_(ctx, ranks) {
  if (ranks.rank() != 0) {
    // Rank 0's config and networks arrive in share_rank0_state.
  } else if (resume) {
    run_ = RunDirectory::resume(run_dir, scene::fingerprint(geometry.scene()));
    // The run's own settings win; only the stopping rule comes from this invocation.
    TrainConfig saved = run_->config();
    saved.steps = config_.steps;
    saved.minutes = config_.minutes;
    config_ = saved;
    network_ = RunDirectory::load_radiance(ctx, run_dir, true);
    if (config_.guided()) guide_ = RunDirectory::load_guide(ctx, run_dir);
    if (lagged()) {
      guide_before_ = RunDirectory::load_guide_before(ctx, run_dir, guide_->config());
      if (guide_before_) before_step_ = guide_->steps() - 1;
    }
    // The log's last row carries the training time so far, so resumed rows continue its time axis.
    seconds_before_ = run_->seconds_trained();
  } else {
    run_ = RunDirectory::create(run_dir);
    if (config_.batch == 0) config_.batch = default_batch(ctx.device());
    config_.network = nn::to_json(radiance_network_config(geometry, sampler_, config_, ctx.device()));
    network_ = std::make_unique<nn::Network>(ctx, nn::network_config_from_json(config_.network));
    if (config_.guided()) {
      config_.guide = nn::to_json(guide_network_config(geometry, sampler_, config_));
      guide_ = std::make_unique<nn::Network>(ctx, nn::network_config_from_json(config_.guide));
    }
    run_->start(config_, scene::fingerprint(geometry.scene()));
  }
  // Before the ranks share rank 0's state: the average travels with it. A resumed run brings its own.
  if (network_ && config_.average_steps > 0 && !network_->averaging()) network_->start_average();
  share_rank0_state();
  if (lagged()) {
    if (!guide_before_) guide_before_ = std::make_unique<nn::Network>(ctx, guide_->config());
    incident_.set_lagged(true);
  }
  residual_power_ = float(config_.relative_power(0.0));
  const auto share = distributed::share_of(std::size_t(config_.batch), ranks.rank(), ranks.size());
  batch_settings_.points = share.count;
  batch_settings_.first_point = share.first;
  batch_settings_.samples = std::size_t(config_.samples);
  batch_settings_.guide = guide_ != nullptr;
  batch_settings_.next_event = config_.nee;
  batch_settings_.bsdf_fraction = guide_ ? float(config_.bsdf_fraction_at(0.0)) : 1.0f;
  non_finite_.fill(0u);
  set_schedule(default_schedule());
}

void Trainer::set_schedule(StepSchedule schedule) {
  schedule_ = schedule;
  incident_.set_pinned_uploads(schedule == StepSchedule::Pipelined);
  prepared_.reset();
}

BatchSettings Trainer::settings_for(std::uint64_t step) const {
  BatchSettings settings = batch_settings_;
  // run() sets c from the spent fraction of the budget, which for a step budget alone is step / steps (the same
  // arithmetic, so a batch traced ahead with it is the batch the step asks for).
  if (guide_ && config_.steps > 0 && config_.minutes <= 0 && !hold_radiance_)
    settings.bsdf_fraction = float(config_.bsdf_fraction_at(double(step) / double(config_.steps)));
  return settings;
}

void Trainer::prepare_ahead(std::uint64_t step) {
  const BatchSettings settings = settings_for(step);
  take_points(step, settings);
  // ISNR guides a share 1 - c of the directions from the first step on (the warm-up ramps c down from 1). Without
  // the lag those need step k+1's lobes, i.e. the I-Module after step k's update: only a run with c = 1 throughout
  // traces ahead. With the lag they were drawn early in step k and are read back by now.
  const bool trace = lagged() || (!IncidentSampling::guided(settings) && (!guide_ || config_.bsdf_fraction >= 1.0));
  if (trace) incident_.trace(*geometry_, settings, config_.seed, step, batch_);
  // The lag draws the lobes of step k+2 during step k+1: their points are drawn now, on the host's time.
  if (lagged() && continues_after(step)) draw_next_points(step + 1, settings);
  prepared_ = Prepared{step, settings, trace};
}

StepStats Trainer::step() {
  // Both modules step together, so their counts agree unless the N-Module is held.
  const std::uint64_t step = guide_ ? guide_->steps() : network_->steps();
  // A batch prepared ahead serves this step only if it was drawn for it with these settings (run() changes c and
  // the schedules between steps; the points do not depend on c).
  bool ahead = false, traced = false;
  if (prepared_) {
    BatchSettings drawn = prepared_->settings;
    if (!prepared_->traced) drawn.bsdf_fraction = batch_settings_.bsdf_fraction;
    ahead = prepared_->step == step && drawn == batch_settings_;
    traced = ahead && prepared_->traced;
    prepared_.reset();
  }
  if (ahead) ++steps_prepared_ahead_;
  const bool pipelined = schedule_ == StepSchedule::Pipelined;
  if (!ahead) take_points(step, batch_settings_);
  const std::size_t M = batch_.points, N = batch_.samples;
  upload_rows(batch_, point_rows_up_, point_rows_);
  if (batch_.times) ++batch_.times->steps;
  // The I-Module's lobes at the points, activations kept for its backward.
  if (guide_) {
    guide_->forward_train(point_rows_, M, guide_ctx_);
    incident_.decode(guide_ctx_.output(), batch_);
  }
  if (lagged()) draw_lagged_lobes(step);
  if (!traced) incident_.trace(*geometry_, batch_settings_, config_.seed, step, batch_);
  incident_.upload(batch_settings_, batch_);
  if (lagged()) incident_.advance(step);
  const std::size_t K = batch_.lookups();
  cl::reserve(*ctx_, incident_radiance_, K * 3);
  cl::reserve(*ctx_, rhs_, M * 3);
  cl::reserve(*ctx_, d_output_, M * 3);

  // sg(L_α) at the incident hits: inference only, no activations kept.
  if (K) network_->infer(incident_.incident_rows, K, incident_radiance_);
  rhs_kernel_
      .args(incident_.weight, incident_.emitted, incident_.pdf, incident_.lookup, incident_radiance_, unsigned(M),
            unsigned(N), rhs_, non_finite_)
      .launch(M);
  incident_.add_direct(rhs_, non_finite_);  // delta lights' next-event term, where the scene has any
  if (!hold_radiance_) {
    network_->forward_train(point_rows_, M, train_ctx_);
    // Mean over points and channels, so the learning rate does not depend on the batch size.
    // The right-hand side is in radiance (infer applies the output scale); the raw outputs are in its units.
    // Over the global batch: the ranks' gradients, summed, are the one-process gradient.
    loss_.evaluate(train_ctx_.output(), rhs_, M * 3, 1.0f / float(std::size_t(config_.batch) * 3), residual_power_,
                   d_output_, 1.0f / network_->config().output_scale);
    network_->backward(train_ctx_, d_output_);
    exchange_.reduce(*network_);
    network_->adam_step();
    if (network_->averaging()) network_->update_average(float(config_.average_decay(long(network_->steps()) - 1)));
  }
  if (guide_) {
    // The I-Module learns from the same samples and the N-Module's radiance before its update (sg(L_α)).
    cl::reserve(*ctx_, d_lobes_, M * kVmfRaw);
    // F from the N-Module at the points: the forward above kept its raw outputs (radiance / output scale); a held
    // N-Module ran no forward.
    float scale = network_->config().output_scale;
    if (hold_radiance_) {
      cl::reserve(*ctx_, point_radiance_, M * 3);
      network_->infer(point_rows_, M, point_radiance_);
      scale = 1.0f;
    }
    const cl::Buffer<float>& scattered = hold_radiance_ ? point_radiance_ : train_ctx_.output();
    incident_.vmf().loss(incident_.guide_samples(incident_radiance_, scattered, scale), N,
                         config_.is_loss == IsLoss::Ikl, d_lobes_, std::size_t(config_.batch));
    guide_->backward(guide_ctx_, d_lobes_);
    exchange_.reduce(*guide_);
    if (lagged()) {
      // The parameters step k+1's directions were drawn from (early in this step), kept for a checkpoint.
      guide_before_->copy_parameters(*guide_);
      before_step_ = step;
    }
    guide_->adam_step();
  }
  StepStats stats;
  stats.lookups = K;
  stats.guided = batch_.guided;
  // Step k's network math is enqueued and needs none of batch_'s host arrays any more (uploads copied them): the
  // host prepares step k+1 while the device computes. Not after the run's last step.
  if (pipelined && continues_after(step)) {
    cl::flush(*ctx_);
    prepare_ahead(step + 1);
  }
  return stats;
}

void Trainer::take_points(std::uint64_t step, const BatchSettings& settings) {
  if (next_points_ == step) {
    std::swap(batch_, next_batch_);
    next_points_.reset();
  } else {
    sample_training_points(sampler_, geometry_->scene(), settings, config_.seed, step, batch_);
  }
}

void Trainer::draw_next_points(std::uint64_t step, const BatchSettings& settings) {
  if (next_points_ == step) return;
  sample_training_points(sampler_, geometry_->scene(), settings, config_.seed, step, next_batch_);
  next_points_ = step;
}

void Trainer::upload_rows(const TrainingBatch& batch, cl::PinnedUpload<float>& pinned, cl::Buffer<float>& rows) {
  const StageTimer timer(batch, &HostStageTimes::uploads, ctx_);
  if (schedule_ == StepSchedule::Pipelined)
    pinned.send(*ctx_, rows, batch.point_rows);
  else
    cl::upload(*ctx_, rows, batch.point_rows);
}

void Trainer::draw_lagged_lobes(std::uint64_t step) {
  const std::size_t M = batch_.points;
  if (!incident_.drawn_ahead(step)) {
    // A session's first step: its directions come from the I-Module before the last update where the checkpoint
    // kept it (what an uninterrupted run drew them from), else from the current one (the run's first step).
    if (guide_before_ && before_step_ && *before_step_ + 1 == step) {
      cl::reserve(*ctx_, sampling_raw_, M * kVmfRaw);
      guide_before_->infer(point_rows_, M, sampling_raw_);
      incident_.decode_sampling(sampling_raw_, batch_);
    } else {
      incident_.decode_sampling(guide_ctx_.output(), batch_);
    }
  }
  if (!continues_after(step)) return;
  // Step k+1's lobes from the I-Module before this step's update, its directions drawn and read back while the
  // device goes on with this step's networks.
  draw_next_points(step + 1, batch_settings_);
  upload_rows(next_batch_, next_rows_up_, next_rows_);
  cl::reserve(*ctx_, next_raw_, M * kVmfRaw);
  guide_->infer(next_rows_, M, next_raw_);
  incident_.draw_ahead(next_raw_, next_batch_, config_.seed, step + 1);
}

void Trainer::save_checkpoint() const {
  // The copy of the I-Module before its update is the one the next step draws from only right after that update.
  const bool before = guide_before_ && before_step_ && *before_step_ + 1 == guide_->steps();
  if (run_) run_->save_model(*network_, guide_.get(), before ? guide_before_.get() : nullptr);
}

void Trainer::save_snapshot(const fs::path& dir) const {
  if (run_) run_->write_snapshot(dir, config_, *network_, guide_.get());
}

void Trainer::run(const RunOptions& options) {
  install_stop_handlers();
  const double budget_s = config_.minutes * 60.0;
  const auto start = std::chrono::steady_clock::now();
  // Not training time: spent in options.after_step, or stopped (SIGSTOP, Ctrl-Z) — a pause counted as training
  // would end the budget at once, unannealed.
  double outside_s = 0;
  double typical_step_s = 0;  // the last uninterrupted loop iteration: what a paused one is counted as
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - outside_s;
  };
  const double budget_before_s = options.minutes_in_total ? seconds_before_ : 0.0;
  const double total = config_.steps > 0 ? double(config_.steps) : budget_s;
  const auto first_step = long(network_->steps());
  Progress progress("train", total, 5.0, config_.steps > 0 ? double(first_step) : budget_before_s);
  double loss_sum = 0;
  long loss_steps = 0;
  std::size_t lookups = 0, guided = 0;
  std::string last;
  // The spent fraction of whichever budget ends the run first.
  const auto spent = [&] {
    double f = 0;
    if (config_.steps > 0) f = double(network_->steps()) / double(config_.steps);
    if (budget_s > 0) f = std::max(f, (budget_before_s + elapsed()) / budget_s);
    return f;
  };
  // Ranks agree on stopping and on the budget spent (the learning rate follows it), or their models would part.
  const distributed::Communicator& ranks = exchange_.communicator();
  double lr_scale = 1;
  long last_evaluated = -1;
  LogRow last_row;  // the row last written, for the run's final evaluation when no row follows it
  // A hook (evaluation, after_step) runs between steps, where the parameters are whole: should it throw, the steps
  // trained so far are checkpointed before the exception leaves (a failure of that write gives way to the hook's).
  const auto guarded = [&](auto&& hook) {
    try {
      return hook();
    } catch (...) {
      try {
        save_checkpoint();
      } catch (...) {
      }
      throw;
    }
  };
  // The model's figures for `now`'s row, timed out of the training time.
  const auto evaluation = [&](long now) {
    const auto evaluate_start = std::chrono::steady_clock::now();
    // The model evaluated is the weight average, swapped in for the evaluation only (and back before a failed
    // evaluation's checkpoint is written).
    const std::optional<image::Metrics> m = guarded([&] {
      const nn::AverageSwapped average(*network_);
      return options.evaluate();
    });
    outside_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - evaluate_start).count();
    last_evaluated = now;
    return m;
  };
  // One row of log.csv over the steps since the last one.
  const auto log_row = [&](long now, bool evaluate) {
    nn::LossValue v = loss_.take();
    nn::LossValue g = guide_ ? incident_.vmf().take() : nn::LossValue{0, 0};
    // Incident terms dropped while forming the right-hand side count too: they never reach the loss, so the
    // loss's own count cannot see them.
    std::uint32_t rhs_dropped = non_finite_.read()[0];
    non_finite_.fill(0u);
    if (ranks.distributed()) {
      // Each rank's loss is its share of the global batch's mean: the row is their sum.
      double totals[] = {v.loss, g.loss, double(v.non_finite + g.non_finite + rhs_dropped), double(lookups),
                         double(guided)};
      ranks.sum(totals);
      v = {totals[0], std::uint32_t(totals[2])};
      g = {totals[1], 0};
      rhs_dropped = 0;
      lookups = std::size_t(totals[3]);
      guided = std::size_t(totals[4]);
    }
    loss_sum = v.loss / double(loss_steps);
    const double samples = double(loss_steps * config_.batch * config_.samples);
    last_row = {.step = now,
                .seconds = seconds_before_ + elapsed(),
                .loss = loss_sum,
                .lookups = double(lookups) / samples,
                .non_finite = v.non_finite + g.non_finite + rhs_dropped,
                .learning_rate = lr_scale * double(network_->config().adam.learning_rate_at(std::uint64_t(now))),
                .residual_power = double(residual_power_),
                .guide_loss = g.loss / double(loss_steps),
                .guided_share = double(guided) / samples,
                .evaluation = std::nullopt};
    if (evaluate) last_row.evaluation = evaluation(now);
    if (run_) run_->append_log(last_row);
    char detail[128];
    std::snprintf(detail, sizeof detail, "step %ld  loss %.4g  %.2f steps/s", now, loss_sum,
                  double(now - first_step) / std::max(1e-9, elapsed()));
    last = detail;
    loss_steps = 0;
    lookups = 0;
    guided = 0;
  };
  while (ranks.max(stop_requested() ? 1.0 : 0.0) == 0.0) {
    const unsigned continued = continue_count();
    const double iteration_start = elapsed();
    const double fraction = ranks.max(spent());
    if (fraction >= 1.0) break;
    lr_scale = config_.learning_rate_scale(fraction, long(network_->steps()));
    network_->set_learning_rate_scale(float(lr_scale));
    if (guide_) guide_->set_learning_rate_scale(float(lr_scale));
    residual_power_ = float(config_.relative_power(fraction));
    if (guide_) batch_settings_.bsdf_fraction = float(config_.bsdf_fraction_at(fraction));
    const StepStats stats = last_step_ = step();
    lookups += stats.lookups;
    guided += stats.guided;
    ++loss_steps;
    const long now = long(network_->steps());
    // The last step is known here for a step budget (and for a time budget spent already): its row carries the
    // final evaluation.
    const bool evaluate_now = options.evaluate && ((options.evaluate_every > 0 && now % options.evaluate_every == 0) ||
                                                   (!stop_requested() && spent() >= 1.0));
    if (now % config_.log_every == 0 || evaluate_now) log_row(now, evaluate_now);
    if (now % kRankCheckEvery == 0) check_ranks_agree(std::uint64_t(now));
    if (now % config_.checkpoint_every == 0) save_checkpoint();
    const double iteration_s = elapsed() - iteration_start;
    if (continue_count() != continued)
      outside_s += std::max(0.0, iteration_s - typical_step_s);
    else
      typical_step_s = iteration_s;
    progress.update(config_.steps > 0 ? double(now) : budget_before_s + elapsed(), last);
    seconds_this_session_ = elapsed();
    if (options.after_step) {
      const auto hook_start = std::chrono::steady_clock::now();
      guarded([&] { options.after_step(seconds_trained()); });
      outside_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - hook_start).count();
    }
  }
  seconds_this_session_ = elapsed();
  // The steps since the last row get one too, so that log.csv's time axis ends where the training did: a resumed
  // run (and a sweep's budget in total) starts from it.
  const long end = long(network_->steps());
  const bool evaluate_end = options.evaluate && !stop_requested() && last_evaluated != end && end > first_step;
  if (loss_steps > 0) {
    log_row(end, evaluate_end);
  } else if (evaluate_end && run_) {
    // A time budget ran out after a row was logged at its last step: that row gains the evaluation.
    last_row.evaluation = evaluation(end);
    run_->replace_last_log_row(last_row);
  }
  check_ranks_agree(network_->steps());
  save_checkpoint();
  progress.finish(last + (stop_requested() ? "  (stopped by signal; checkpoint written)" : ""));
}

}  // namespace clr::radiosity
