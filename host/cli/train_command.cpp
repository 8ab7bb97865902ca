// clradiosity train SCENE.xml [--method isnr|nr] [--is-loss ikl|kl] [--bsdf-fraction C] [--samples N] [--batch M]
//                  [--steps S | --minutes T] [--preset preview|balanced|quality|paper] [--seed K] [--config FILE.json]
//                  [--reference REF.exr [--eval-every S] [--eval-spp K]] [--preview FILE.png [--preview-every S]]
//                  [--resume] -o RUN_DIR
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/folder_record.hpp"
#include "common/input_file.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "distributed/communicator.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "image/image_format.hpp"
#include "radiosity/convergence.hpp"
#include "radiosity/preset.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "scene/fingerprint.hpp"

namespace clr::cli {
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
void require_same_settings(const radiosity::TrainConfig& given, const radiosity::TrainConfig& saved,
                           const std::function<bool(const char*)>& flag_given) {
  const nlohmann::json g = given, s = saved;
  for (const auto& [flag, pointer] : {std::pair{"--method", "/method"},
                                      {"--is-loss", "/is_loss"},
                                      {"--bsdf-fraction", "/bsdf_fraction"},
                                      {"--samples", "/samples"},
                                      {"--batch", "/batch"},
                                      {"--seed", "/seed"},
                                      {"--residual", "/residual"},
                                      {"--learning-rate", "/network/adam/learning_rate"},
                                      {"--guide-learning-rate", "/guide/adam/learning_rate"},
                                      {"--gemm", "/network/gemm"}}) {
    if (!flag_given(flag)) continue;
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

Command add_train_command(CLI::App& app) {
  struct Options {
    std::string scene, run_dir, config_file, device, method, is_loss, residual, gemm, preset, preview;
    std::map<std::string, std::string> parameters;
    int samples = 0, batch = 0;
    long steps = 0, preview_every = 0;
    radiosity::EvaluationSettings evaluation;
    double minutes = 0, learning_rate = 0, bsdf_fraction = 0, guide_learning_rate = 0;
    std::uint64_t seed = 0;
    bool resume = false, other_scene = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("train", "Train a Neural Radiosity model of a scene into RUN_DIR");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("-o,--output", opt->run_dir, "Run directory (config.json, log.csv, model.clr)")->required();
  cmd->add_option("--method", opt->method,
                  "isnr (default: importance sampling by the jointly trained I-Module) or nr (BSDF sampling only)")
      ->check(CLI::IsMember({"isnr", "nr"}));
  cmd->add_option("--is-loss", opt->is_loss, "The I-Module's loss: ikl (Improved KL, default) or kl")
      ->check(CLI::IsMember({"ikl", "kl"}));
  cmd->add_option("--bsdf-fraction", opt->bsdf_fraction,
                  "Share of incident directions drawn from the BSDF, the rest from the I-Module (isnr; default 0.5)")
      ->check(finite_in(0, 1, true));
  cmd->add_option("--guide-learning-rate", opt->guide_learning_rate, "The I-Module's Adam learning rate (default 5e-3)")
      ->check(finite_in(0, 1, true));
  cmd->add_option("--samples", opt->samples, "Incident directions per point (N, default 4)")
      ->check(CLI::Range(1, 1024));
  // 0 means "chosen for the device" in a config file only: on the command line it is a mistake, not a request.
  cmd->add_option("--batch", opt->batch, "Points per step (M; default chosen for the device)")
      ->check(CLI::Range(1, 1 << 22));
  auto* steps = cmd->add_option("--steps", opt->steps, "Stop after this many steps (in total, when resuming)")
                    ->check(integer_at_least(1));
  cmd->add_option("--minutes", opt->minutes, "Stop after this much training time in this session")
      ->check(positive_finite())
      ->excludes(steps);
  cmd->add_option("--seed", opt->seed, "Random seed")->check(integer_at_least(0));
  cmd->add_option("--learning-rate", opt->learning_rate, "Adam learning rate (default 5e-3, ISNR §4.3)")
      ->check(finite_in(0, 1, true));
  cmd->add_option("--residual", opt->residual,
                  "relative (default; fades to l2 by the end of the budget, see relative_fade_end) or l2")
      ->check(CLI::IsMember({"relative", "l2"}));
  cmd->add_option("--gemm", opt->gemm,
                  "Matrix-product backend: auto (timed probe, cached; TF32 tensor cores where faster and within their "
                  "bound), fp32 (the same without TF32), own, clblast")
      ->check(CLI::IsMember({"auto", "own", "clblast"}));
  auto* config_file = cmd->add_option("--config", opt->config_file, "Training settings (JSON); flags override it");
  cmd->add_flag("--other-scene", opt->other_scene,
                "With --config RUN/config.json: take the settings of a run of another scene (its bounding box "
                "and inputs are recomputed for this one)")
      ->needs(config_file);
  auto* resume = cmd->add_flag("--resume", opt->resume, "Continue the run in RUN_DIR from its checkpoint");
  cmd->add_option("--preset", opt->preset,
                  "preview, balanced or quality: batch, N, width and hash-table size picked for that budget, this "
                  "scene and device; paper: the ISNR paper's settings (docs/presets.md). Printed, stored in "
                  "config.json; flags override it")
      ->check(CLI::IsMember(radiosity::preset_names()))
      ->excludes(resume);
  auto* reference_option =
      cmd->add_option("--reference", opt->evaluation.reference,
                      "Log the model's MAPE, MSE and relMSE against this EXR in log.csv every --eval-every steps "
                      "(rendered with the scene's camera at its size, outside the training time) and draw "
                      "RUN_DIR/convergence.svg at the end");
  cmd->add_option("--eval-every", opt->evaluation.every,
                  "Steps between evaluations against --reference (default: the checkpoint interval; the last "
                  "step is evaluated too)")
      ->check(integer_at_least(1))
      ->needs(reference_option);
  cmd->add_option("--eval-spp", opt->evaluation.spp,
                  "Camera rays per pixel of an evaluation (default 4, as `render`; a resumed run keeps its own)")
      ->check(CLI::Range(1, 1 << 16))
      ->needs(reference_option);
  auto* preview_option = cmd->add_option("--preview", opt->preview,
                                         "Keep a small render of the model (PNG, the longer side at most " +
                                             std::to_string(radiosity::kPreviewSide) +
                                             " pixels) up to date, every --preview-every steps and at the end");
  cmd->add_option("--preview-every", opt->preview_every,
                  "Steps between previews (default: --eval-every's, else the checkpoint interval)")
      ->check(integer_at_least(1))
      ->needs(preview_option);
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->parameters);

  return {
      cmd, [opt, cmd]() {
        radiosity::TrainConfig config;
        if (!opt->config_file.empty()) config = radiosity::load_train_config(opt->config_file);
        // Flags given on the command line override the config file and the preset, whatever their value
        // (validate() judges); they are applied before the scene loads, to fail fast, and again over a preset.
        const auto given = [&](const char* flag) { return cmd->count(flag) > 0; };
        const auto apply_flags = [&] {
          if (!opt->method.empty()) config.method = radiosity::parse_method(opt->method, "--method");
          if (!opt->residual.empty()) config.residual = radiosity::parse_residual(opt->residual, "--residual");
          if (!opt->is_loss.empty()) config.is_loss = radiosity::parse_is_loss(opt->is_loss, "--is-loss");
          if (given("--samples")) config.samples = opt->samples;
          if (given("--batch")) config.batch = opt->batch;
          if (given("--steps")) config.steps = opt->steps;
          if (given("--minutes")) config.minutes = opt->minutes;
          if (given("--seed")) config.seed = opt->seed;
          if (given("--learning-rate")) config.network["adam"]["learning_rate"] = opt->learning_rate;
          if (given("--bsdf-fraction")) config.bsdf_fraction = opt->bsdf_fraction;
          if (given("--guide-learning-rate")) config.guide["adam"]["learning_rate"] = opt->guide_learning_rate;
          if (!opt->gemm.empty()) config.network["gemm"] = opt->gemm;
          config.validate();
        };
        apply_flags();
        if (opt->resume) {
          if (!opt->config_file.empty())
            throw InputError("--config with --resume: a resumed run's settings are its own config.json");
          if (std::filesystem::exists(radiosity::RunDirectory::config_path(opt->run_dir)))
            require_same_settings(config, radiosity::RunDirectory::load_config(opt->run_dir), given);
        }
        if (config.steps == 0 && config.minutes == 0 && opt->preset.empty())
          throw InputError("give a budget: --steps S or --minutes T (or a --preset)");

        const auto scene = scene::load_scene(opt->scene, opt->parameters);
        const auto& ranks = distributed::Communicator::world();
        ranks.require_same("the scenes (the contents of their files)",
                           Digest().add(scene::fingerprint(scene).digest).value());
        ranks.require_same("the settings (--config and flags)", Digest().add(nlohmann::json(config).dump()).value());
        scene::require_emitter(scene, opt->scene);
        // What watches the run (--reference, --preview) is checked with the scene, before any training.
        const bool evaluate = !opt->evaluation.reference.empty(), preview = !opt->preview.empty();
        std::optional<image::Image> reference;
        if (evaluate || preview) {
          const char* option = evaluate ? "--reference" : "--preview";
          if (ranks.distributed())
            throw InputError(std::string(option) +
                             " under mpirun: rank 0 alone would render while the other ranks wait (train without it, "
                             "then `render` the checkpoints)");
          scene::require_sensor(scene, opt->scene);
          if (scene.camera.aperture_radius > 0)
            throw InputError(std::string(option) + ": " + opt->scene +
                             " has a thinlens sensor, which only `reference` renders");
          std::vector<std::filesystem::path> inputs = scene.files;
          inputs.push_back(opt->evaluation.reference);
          using RunFiles = radiosity::RunDirectory;
          for (const auto& f : {RunFiles::config_path(opt->run_dir), RunFiles::log_path(opt->run_dir),
                                RunFiles::model_path(opt->run_dir), RunFiles::scene_path(opt->run_dir),
                                RunFiles::evaluation_path(opt->run_dir), RunFiles::convergence_path(opt->run_dir)})
            inputs.push_back(f);
          image::output_format(opt->preview, "--preview", {image::Format::Png});
          require_outputs({{opt->preview, "--preview"}}, inputs);
          if (evaluate) reference = radiosity::read_evaluation_reference(opt->evaluation.reference, scene.camera);
        }
        // A run's config.json holds the networks of its scene (bounding box, inputs): reusing it for another
        // scene is a deliberate act.
        const std::filesystem::path config_run = std::filesystem::path(opt->config_file).parent_path();
        if (!opt->config_file.empty() && !opt->other_scene &&
            std::filesystem::path(opt->config_file).filename() == "config.json" &&
            std::filesystem::exists(radiosity::RunDirectory::scene_path(config_run)))
          radiosity::RunDirectory::require_scene(config_run, scene::fingerprint(scene));
        if (opt->other_scene) config.forget_scene();
        const geometry::Geometry geometry(scene);
        // Under mpirun each rank takes the next of the matching devices on its machine; rank 0 alone writes.
        cl::Context ctx(cl::select_device(opt->device, unsigned(ranks.local_rank())));
        if (!opt->preset.empty()) {
          const geometry::SurfaceSampler sampler(scene);
          const auto why =
              radiosity::apply_preset(opt->preset, config, radiosity::scene_inputs(geometry, sampler), ctx.device());
          if (ranks.rank() == 0)
            if (!Progress::silenced())
              for (const auto& line : why) std::cerr << "preset " << opt->preset << ": " << line << "\n";
          apply_flags();
        }
        radiosity::Trainer trainer(ctx, geometry, config, opt->run_dir, opt->resume, ranks);
        const auto first_step = trainer.steps_done();
        if (ranks.rank() != 0) {
          trainer.run();
          return 0;
        }
        radiosity::Trainer::RunOptions watch;
        const auto field = radiosity::radiance_query(ctx, trainer.network());
        auto& evaluation = opt->evaluation;
        if (evaluate) {
          // A resumed run's columns keep measuring what they measured: its spp unless given, and the same reference.
          const auto record_file = radiosity::RunDirectory::evaluation_path(opt->run_dir);
          if (opt->resume && !given("--eval-spp") && std::filesystem::exists(record_file)) {
            const auto record = read_json_file(record_file, "evaluation record");
            if (record.is_object() && record.contains("spp") && record["spp"].is_number_integer())
              evaluation.spp = record["spp"].get<int>();
          }
          require_same_record(record_file, radiosity::evaluation_record(evaluation, *reference),
                              "evaluation columns in log.csv",
                              {{"reference", "--reference (its pixels)"},
                               {"width", "--reference (its width)"},
                               {"height", "--reference (its height)"},
                               {"spp", "--eval-spp"}});
          if (!given("--eval-every")) evaluation.every = trainer.config().checkpoint_every;
          watch.evaluate_every = evaluation.every;
          watch.evaluate = [&] {
            return radiosity::evaluate_model(geometry, field, *reference, evaluation.spp).metrics;
          };
        }
        const auto write_preview = [&] {
          image::write_png(opt->preview, radiosity::render(geometry, field, radiosity::preview_settings(scene.camera)));
        };
        if (preview) {
          const long every = given("--preview-every") ? opt->preview_every
                             : evaluate               ? evaluation.every
                                                      : trainer.config().checkpoint_every;
          watch.after_step = [&, every](double) {
            if (long(trainer.steps_done()) % every == 0) write_preview();
          };
        }
        if (!Progress::silenced()) {
          std::cerr << "train: " << opt->scene << " on " << ctx.device().describe() << ", "
                    << radiosity::to_string(trainer.config().method) << ", batch " << trainer.config().batch << " × "
                    << trainer.config().samples << " samples, " << trainer.network().parameter_count() << " parameters";
          if (auto* guide = trainer.guide())
            std::cerr << " + I-Module " << guide->parameter_count() << " ("
                      << radiosity::to_string(trainer.config().is_loss) << ", BSDF share "
                      << trainer.config().bsdf_fraction << ")";
          if (ranks.distributed()) std::cerr << ", " << ranks.size() << " MPI ranks";
          std::cerr << "\n";
        }
        trainer.run(watch);
        if (ranks.distributed()) print_exchange(trainer.exchange().stats(), trainer.steps_done() - first_step);
        std::cout << "model: " << opt->run_dir << "/model.clr (" << trainer.steps_done() << " steps)\n";
        // The paper's tables report memory beside time (bench/paper_tables.sh reads this line).
        std::cout << "peak device memory: " << double(ctx.peak_bytes()) / double(1 << 20) << " MiB\n";
        if (preview && !stop_requested()) {
          write_preview();
          std::cout << "preview: " << opt->preview << "\n";
        }
        if (const auto figure = radiosity::write_convergence_figure(opt->run_dir))
          std::cout << "convergence: " << figure->string() << "\n";
        return 0;
      }};
}

}  // namespace clr::cli
