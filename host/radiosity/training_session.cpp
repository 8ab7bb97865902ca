#include "radiosity/training_session.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>

#include "cl/context.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/folder_record.hpp"
#include "common/input_file.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "distributed/communicator.hpp"
#include "geometry/geometry.hpp"
#include "geometry/surface_sampler.hpp"
#include "image/image.hpp"
#include "image/image_format.hpp"
#include "radiosity/environment.hpp"
#include "radiosity/preset.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/scene_inputs.hpp"
#include "radiosity/session_record.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "scene/fingerprint.hpp"

namespace clr::radiosity {
namespace {

// The exchange's cost per step as rank 0 saw it (docs/mpi.md: the scaling model starts from these numbers).
void print_exchange(const distributed::ExchangeStats& s, std::uint64_t steps) {
  if (steps == 0) return;
  const double n = double(steps);
  std::fprintf(
      stderr,
      "mpi: exchange %.1f KiB/step (dense %.1f KiB), %.2f ms/step in MPI_Allreduce, %.2f ms/step exchanging in "
      "all, %.2f ms/step waiting for the slowest rank\n",
      double(s.bytes) / n / 1024.0, double(s.dense_bytes) / n / 1024.0, s.allreduce_seconds / n * 1e3,
      s.total_seconds / n * 1e3, s.wait_seconds / n * 1e3);
}

// A resumed run keeps its settings: a flag that asks for another value than the run has is refused, naming both,
// rather than silently dropped. `given` holds the flags' values (over defaults), `saved` the run's config.
// What watches a run (its preview, evaluations, convergence figure) fails without ending it: a folder replaced, a
// disk full, a file made unwritable mid-run. Each failure is one line on stderr (the first of each output; later
// ones are counted), and the training goes on to its checkpoint.
class SideOutputs {
 public:
  // Runs `write`; false, reported, when it threw.
  bool attempt(const std::string& what, const std::function<void()>& write) {
    try {
      write();
      return true;
    } catch (const std::bad_alloc&) {
      throw;  // the process's own memory: not the output's fault
    } catch (const std::exception& e) {
      if (failed_[what]++ == 0)
        std::cerr << "\ntrain: warning: " << what << " failed (" << clip(e.what(), 240)
                  << "); the training goes on and keeps its checkpoint\n";
      ++failures_;
      return false;
    }
  }
  std::size_t failures() const { return failures_; }

 private:
  std::map<std::string, std::size_t> failed_;
  std::size_t failures_ = 0;
};

// What watches the run, given explicitly (by flag or keyword): the one check of each, for the CLI and Python alike.
void require_watch_settings(const TrainRequest& opt, const std::function<bool(const char*)>& given) {
  const auto at_least_one = [&](const char* flag, long value) {
    if (given(flag) && value < 1)
      throw InputError(std::string(flag) + " must be at least 1, got " + std::to_string(value));
  };
  at_least_one("--eval-every", opt.evaluation.every);
  at_least_one("--preview-every", opt.preview_every);
  if (given("--eval-spp") && (opt.evaluation.spp < 1 || opt.evaluation.spp > kMaxEvaluationSpp))
    throw InputError("--eval-spp must lie in [1, " + std::to_string(kMaxEvaluationSpp) + "], got " +
                     std::to_string(opt.evaluation.spp));
}

void require_same_settings(const radiosity::TrainConfig& given, const radiosity::TrainConfig& saved,
                           const std::function<bool(const char*)>& flag_given) {
  const nlohmann::json g = given, s = saved;
  for (const auto& [flag, pointer, fixed] : setting_flags()) {
    if (!fixed || !flag_given(flag)) continue;
    const nlohmann::json::json_pointer at(pointer);
    const nlohmann::json want = g.value(at, nlohmann::json()), have = s.value(at, nlohmann::json());
    // Learning rates are stored as float: equal to a double up to its precision.
    const bool same = want.is_number() && have.is_number()
                          ? std::abs(want.get<double>() - have.get<double>()) <= 1e-6 * std::abs(have.get<double>())
                          : want == have;
    if (!same)
      throw InputError("--resume: " + std::string(flag) + " " + clip(want.dump()) + " contradicts the run's " +
                       clip(have.dump()) + " (a resumed run keeps its settings; start a new run to change them)");
  }
}

}  // namespace

const std::vector<SettingFlag>& setting_flags() {
  static const std::vector<SettingFlag> flags = {{"--method", "/method", true},
                                                 {"--is-loss", "/is_loss", true},
                                                 {"--bsdf-fraction", "/bsdf_fraction", true},
                                                 {"--samples", "/samples", true},
                                                 {"--batch", "/batch", true},
                                                 {"--seed", "/seed", true},
                                                 {"--residual", "/residual", true},
                                                 {"--nee", "/nee", true},
                                                 {"--learning-rate", "/network/adam/learning_rate", true},
                                                 {"--guide-learning-rate", "/guide/adam/learning_rate", true},
                                                 {"--gemm", "/network/gemm", true},
                                                 {"--steps", "/steps", false},
                                                 {"--minutes", "/minutes", false}};
  return flags;
}

namespace {

// train() but for the cleanup of a run that never checkpointed.
TrainOutcome train_run(const TrainRequest& request) {
  const auto& opt = request;
  TrainConfig config;
  if (!opt.config_file.empty()) config = load_train_config(opt.config_file);
  if (!opt.config.is_null()) config = parse_train_config(opt.config);
  // Settings given explicitly override the config file and the preset, whatever their value (validate()
  // judges); they are applied before the scene loads, to fail fast, and again over a preset.
  const auto given = [&](const char* flag) { return opt.given && opt.given(flag); };
  const auto apply_flags = [&] {
    if (opt.settings) opt.settings(config);
    config.validate();
  };
  apply_flags();
  require_watch_settings(opt, given);
  if (opt.resume) {
    if (!opt.config_file.empty() || !opt.config.is_null())
      throw InputError("--config with --resume: a resumed run's settings are its own config.json");
    if (std::filesystem::exists(RunDirectory::config_path(opt.run_dir)))
      require_same_settings(config, RunDirectory::load_config(opt.run_dir), given);
  }
  if (config.steps == 0 && config.minutes == 0 && opt.preset.empty())
    throw InputError("give a budget: --steps S or --minutes T (or a --preset)");

  // A scene loaded already (Python's Scene) trains as it was loaded: its file re-read by a relative path after a
  // chdir, or after an edit, would be another scene.
  std::optional<scene::Scene> read;
  const scene::Scene& scene =
      opt.loaded ? *opt.loaded : read.emplace(scene::load_scene(opt.scene, opt.parameters, opt.sensor));
  const auto& ranks = distributed::Communicator::world();
  ranks.require_same("the scenes (the contents of their files)",
                     Digest().add(scene::fingerprint(scene).digest).value());
  ranks.require_same("the settings (--config and flags)", Digest().add(nlohmann::json(config).dump()).value());
  scene::require_emitter(scene, opt.scene);
  // What watches the run (--reference, --preview) is checked with the scene, before any training.
  const bool evaluate = !opt.evaluation.reference.empty(), preview = !opt.preview.empty();
  std::optional<image::Image> reference;
  if (evaluate || preview) {
    const char* option = evaluate ? "--reference" : "--preview";
    if (ranks.distributed())
      throw InputError(std::string(option) +
                       " under mpirun: rank 0 alone would render while the other ranks wait (train without it, "
                       "then `render` the checkpoints)");
    scene::require_sensor(scene, opt.scene);
    if (scene.camera.aperture_radius > 0)
      throw InputError(std::string(option) + ": " + opt.scene +
                       " has a thinlens sensor, which only `reference` renders");
    std::vector<std::filesystem::path> inputs = scene.files;
    inputs.push_back(opt.evaluation.reference);
    using RunFiles = RunDirectory;
    for (const auto& f :
         {RunFiles::config_path(opt.run_dir), RunFiles::log_path(opt.run_dir), RunFiles::model_path(opt.run_dir),
          RunFiles::scene_path(opt.run_dir), RunFiles::evaluation_path(opt.run_dir),
          RunFiles::convergence_path(opt.run_dir), RunFiles::sessions_path(opt.run_dir)})
      inputs.push_back(f);
    image::output_format(opt.preview, "--preview", {image::Format::Png});
    require_outputs({{opt.preview, "--preview"}}, inputs);
    if (evaluate) reference = read_evaluation_reference(opt.evaluation.reference, scene, opt.sensor);
  }
  // A run's config.json holds the networks of its scene (bounding box, inputs): reusing it for another
  // scene is a deliberate act.
  const std::filesystem::path config_run = std::filesystem::path(opt.config_file).parent_path();
  if (!opt.config_file.empty() && !opt.other_scene &&
      std::filesystem::path(opt.config_file).filename() == "config.json" &&
      std::filesystem::exists(RunDirectory::scene_path(config_run)))
    RunDirectory::require_scene(config_run, scene::fingerprint(scene));
  if (opt.other_scene) config.forget_scene();
  const geometry::Geometry geometry(scene);
  // Under mpirun each rank takes the next of the matching devices on its machine; rank 0 alone writes.
  cl::Context ctx(cl::select_device(opt.device, unsigned(ranks.local_rank())));
  SessionRecord session;  // what the run's sessions.json will say of this session
  if (!opt.preset.empty()) {
    const geometry::SurfaceSampler sampler(scene);
    const auto why = apply_preset(opt.preset, config, scene_inputs(geometry, sampler), ctx.device());
    session.preset = opt.preset;
    session.preset_choices = why;
    if (ranks.rank() == 0)
      if (!Progress::silenced())
        for (const auto& line : why) std::cerr << "preset " << opt.preset << ": " << line << "\n";
    apply_flags();
  }
  Trainer trainer(ctx, geometry, config, opt.run_dir, opt.resume, ranks);
  const auto first_step = trainer.steps_done();
  if (ranks.rank() != 0) {
    trainer.run();
    TrainOutcome other_rank;
    other_rank.rank_zero = false;
    return other_rank;
  }
  SideOutputs side_outputs;
  Trainer::RunOptions watch;
  const auto field = radiance_query(ctx, trainer.network());
  auto evaluation = opt.evaluation;
  evaluation.sensor = opt.sensor;
  if (evaluate) {
    // A resumed run's columns keep measuring what they measured: its spp and image mode unless given, and the same
    // reference. The record names the mode only where it is rhs, so an lhs given against it is refused here.
    const auto record_file = RunDirectory::evaluation_path(opt.run_dir);
    if (opt.resume && std::filesystem::exists(record_file)) {
      const auto record = read_json_file(record_file, "evaluation record");
      if (!given("--eval-spp") && record.is_object() && record.contains("spp") && record["spp"].is_number_integer())
        evaluation.spp = record["spp"].get<int>();
      const bool recorded_rhs = record.is_object() && record.contains("mode") && record["mode"] == "rhs";
      if (!given("--eval-mode")) evaluation.mode = recorded_rhs ? RenderMode::rhs : RenderMode::lhs;
      if (recorded_rhs && evaluation.mode != RenderMode::rhs)
        throw InputError(opt.run_dir + " holds evaluation columns in log.csv made with other settings: " +
                         "--eval-mode was rhs, now lhs (" + record_file.string() +
                         "); results made both ways would share one folder: use another");
    }
    require_same_record(record_file, evaluation_record(evaluation, *reference), "evaluation columns in log.csv",
                        {{"reference", "--reference (its pixels)"},
                         {"width", "--reference (its width)"},
                         {"height", "--reference (its height)"},
                         {"spp", "--eval-spp"},
                         {"mode", "--eval-mode"},
                         {"sensor", "--sensor"}});
    if (!given("--eval-every")) evaluation.every = trainer.config().checkpoint_every;
    watch.evaluate_every = evaluation.every;
    watch.evaluate = [&]() -> std::optional<image::Metrics> {
      std::optional<image::Metrics> m;
      side_outputs.attempt("an evaluation against --reference", [&] {
        m = evaluate_model(geometry, field, *reference, evaluation.spp, evaluation.mode).metrics;
      });
      return m;
    };
  }
  const auto write_preview = [&] {
    return side_outputs.attempt("--preview " + opt.preview, [&] {
      const nn::AverageSwapped average(trainer.network());  // the preview shows the model the run renders
      image::write_png(opt.preview, render(geometry, field, preview_settings(scene.camera)));
    });
  };
  const long preview_every = given("--preview-every") ? opt.preview_every
                             : evaluate               ? evaluation.every
                                                      : trainer.config().checkpoint_every;
  if (preview || opt.after_step)
    watch.after_step = [&](double seconds) {
      if (preview && long(trainer.steps_done()) % preview_every == 0) write_preview();
      if (opt.after_step) opt.after_step(trainer, seconds);
    };
  if (!Progress::silenced()) {
    std::cerr << "train: " << opt.scene << " on " << ctx.device().describe() << ", "
              << to_string(trainer.config().method) << ", batch " << trainer.config().batch << " × "
              << trainer.config().samples << " samples, " << trainer.network().parameter_count() << " parameters";
    if (auto* guide = trainer.guide())
      std::cerr << " + I-Module " << guide->parameter_count() << " (" << to_string(trainer.config().is_loss)
                << ", BSDF share " << trainer.config().bsdf_fraction << ")";
    if (ranks.distributed()) std::cerr << ", " << ranks.size() << " MPI ranks";
    std::cerr << "\n";
  }
  trainer.run(watch);
  if (ranks.distributed()) print_exchange(trainer.exchange().stats(), trainer.steps_done() - first_step);
  TrainOutcome outcome;
  outcome.model = RunDirectory::model_path(opt.run_dir);
  outcome.steps = trainer.steps_done();
  outcome.peak_device_mib = double(ctx.peak_bytes()) / double(1 << 20);
  // The session's record, a stopped one's too (its checkpoint is the run's state); like the other side outputs, its
  // failure (a damaged sessions.json, left as it is) costs the training nothing.
  side_outputs.attempt("the session record " + RunDirectory::sessions_path(opt.run_dir).string(), [&] {
    const SessionRecord now = this_session();
    session.software = now.software;
    session.commit = now.commit;
    session.finished = now.finished;
    session.peak_resident_mib = now.peak_resident_mib;
    session.device = ctx.device().describe();
    session.first_step = first_step;
    session.last_step = trainer.steps_done();
    session.training_seconds = trainer.seconds_trained();
    session.peak_device_mib = outcome.peak_device_mib;
    session.stopped = stop_requested();
    append_session_record(opt.run_dir, session);
  });
  if (preview && !stop_requested()) outcome.preview_written = write_preview();
  side_outputs.attempt("the convergence figure", [&] { outcome.convergence = write_convergence_figure(opt.run_dir); });
  outcome.side_output_failures = side_outputs.failures();
  return outcome;
}

}  // namespace

// A fresh run that fails before its first checkpoint (out of memory while its buffers are made, a device error in
// its first steps) could be neither resumed (no checkpoint) nor started again (its folder is not empty): the files
// it wrote are removed, leaving the folder as it was. Only a folder that was absent or empty is touched.
TrainOutcome train(const TrainRequest& request) {
  check_environment();  // before any file of the run is written (the Python module comes here directly)
  std::error_code ec;
  const std::filesystem::path dir = request.run_dir;
  const bool fresh = !request.resume && (!std::filesystem::exists(dir, ec) || std::filesystem::is_empty(dir, ec));
  try {
    return train_run(request);
  } catch (...) {
    if (fresh && !std::filesystem::exists(RunDirectory::model_path(dir), ec))
      for (const auto& file :
           {RunDirectory::config_path(dir), RunDirectory::log_path(dir), RunDirectory::scene_path(dir),
            RunDirectory::evaluation_path(dir), RunDirectory::convergence_path(dir)})
        std::filesystem::remove(file, ec);
    throw;
  }
}

}  // namespace clr::radiosity
