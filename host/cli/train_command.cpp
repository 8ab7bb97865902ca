// clradiosity train SCENE.xml [--method isnr|nr] [--is-loss ikl|kl] [--bsdf-fraction C] [--samples N] [--batch M]
//                  [--steps S | --minutes T] [--preset preview|balanced|quality|paper] [--seed K] [--config FILE.json]
//                  [--reference REF.exr [--eval-every S] [--eval-spp K] [--eval-mode lhs|rhs]] [--preview FILE.png
//                  [--preview-every S]]
//                  [--report REPORT.html] [--resume] -o RUN_DIR
#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/stop_signal.hpp"
#include "radiosity/preset.hpp"
#include "radiosity/training_session.hpp"
#include "report/run_report.hpp"

namespace clr::cli {
Command add_train_command(CLI::App& app) {
  struct Options {
    std::string scene, run_dir, config_file, device, method, is_loss, residual, nee, gemm, preset, preview, report;
    std::map<std::string, std::string> parameters;
    int sensor = 0;
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
  cmd->add_option("--nee", opt->nee,
                  "on (default): next-event estimation of area lights and the environment, with MIS, in the "
                  "right-hand side; off: the paper's estimator, emitters found by the sampled directions alone")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--gemm", opt->gemm,
                  "Matrix-product backend: auto (timed probe, cached; TF32 tensor cores where faster and within their "
                  "bound), fp32 (the same without TF32), own, clblast")
      ->check(CLI::IsMember({"auto", "fp32", "own", "clblast"}));
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
      ->needs(reference_option);
  cmd->add_option("--eval-spp", opt->evaluation.spp,
                  "Camera rays per pixel of an evaluation (default 4, as `render`; a resumed run keeps its own; at "
                  "most 65536)")
      ->needs(reference_option);
  cmd->add_option("--eval-mode", opt->evaluation.mode,
                  "The evaluated image, as `render --mode`: lhs (default) or rhs (a resumed run keeps its own)")
      ->transform(CLI::CheckedTransformer(radiosity::render_mode_names()))
      ->needs(reference_option);
  auto* preview_option = cmd->add_option("--preview", opt->preview,
                                         "Keep a small render of the model (PNG, the longer side at most " +
                                             std::to_string(radiosity::kPreviewSide) +
                                             " pixels) up to date, every --preview-every steps and at the end");
  cmd->add_option("--preview-every", opt->preview_every,
                  "Steps between previews (default: --eval-every's, else the checkpoint interval)")
      ->needs(preview_option);
  cmd->add_option("--report", opt->report,
                  "At the end, the run's report page (.html, as `clradiosity report` makes it: the model and the path "
                  "tracer at the run's training time beside --reference)");
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->parameters);
  add_sensor_option(*cmd, opt->sensor);

  return {cmd, [opt, cmd]() {
            if (!opt->report.empty()) report::require_report_path(opt->report, "--report");
            radiosity::TrainRequest request;
            request.scene = opt->scene;
            request.parameters = opt->parameters;
            request.sensor = opt->sensor;
            request.run_dir = opt->run_dir;
            request.device = opt->device;
            request.preset = opt->preset;
            request.config_file = opt->config_file;
            request.resume = opt->resume;
            request.other_scene = opt->other_scene;
            request.evaluation = opt->evaluation;
            request.preview = opt->preview;
            request.preview_every = opt->preview_every;
            // Flags given on the command line override the config file and the preset, whatever their value.
            request.given = [cmd](const char* flag) { return cmd->count(flag) > 0; };
            request.settings = [opt, given = request.given](radiosity::TrainConfig& config) {
              if (!opt->method.empty()) config.method = radiosity::parse_method(opt->method, "--method");
              if (!opt->residual.empty()) config.residual = radiosity::parse_residual(opt->residual, "--residual");
              if (!opt->nee.empty()) config.nee = opt->nee == "on";
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
            };
            const auto outcome = radiosity::train(request);
            if (!outcome.rank_zero) return 0;
            std::cout << "model: " << outcome.model.string() << " (" << outcome.steps << " steps)\n";
            // The paper's tables report memory beside time (bench/paper_tables.sh reads this line).
            std::cout << "peak device memory: " << outcome.peak_device_mib << " MiB\n";
            if (outcome.preview_written) std::cout << "preview: " << opt->preview << "\n";
            if (outcome.convergence) std::cout << "convergence: " << outcome.convergence->string() << "\n";
            // The report is made from the finished run as `report` makes it; like the other side outputs, its
            // failure costs the training nothing (one warning line, exit 0), and a stopped run gets none.
            std::size_t failures = outcome.side_output_failures;
            if (!opt->report.empty() && !stop_requested()) try {
                report::RunReportOptions options;
                options.run = opt->run_dir;
                options.reference = opt->evaluation.reference;
                options.scene = opt->scene;
                options.sensor = opt->sensor;
                options.device = opt->device;
                write_run_report(options, opt->report);
              } catch (const std::exception& e) {
                std::cerr << "train: warning: --report " << opt->report << " failed (" << e.what()
                          << "); the model and its checkpoint are complete\n";
                ++failures;
              }
            if (failures > 0)
              std::cerr << "train: " << failures
                        << " preview, evaluation, figure or report write(s) failed (reported above); the model and its "
                           "checkpoint are complete\n";
            return 0;
          }};
}

}  // namespace clr::cli
