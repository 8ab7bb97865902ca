// clradiosity sweep SCENE.xml -o SWEEP_DIR [--reference REF.exr] [--minutes T1,T2,…] [--methods nr,isnr-kl,isnr-ikl]
//                   [--samples 4,32] [--seeds K] [--width W --height H] [--spp S] [--config FILE.json] [--device D]
#include <cstdio>

#include "cli/command.hpp"
#include "cli/data_files.hpp"
#include "cli/number_checks.hpp"
#include "radiosity/train_config.hpp"
#include "sweep/sweep.hpp"

namespace clr::cli {

Command add_sweep_command(CLI::App& app) {
  struct Options {
    sweep::SweepOptions sweep;
    std::string config_file, device;
  };
  auto opt = std::make_shared<Options>();
  auto& s = opt->sweep;
  s.minutes = {1, 2, 5, 10};
  s.methods = {"nr", "isnr-ikl"};
  s.samples = {4};
  auto* cmd = app.add_subcommand(
      "sweep",
      "Training time against accuracy: train each method × N × seed once with a snapshot at every budget, "
      "render and measure each, beside the path tracer at equal time (results.csv, tables.md, figures)");
  cmd->add_option("scene", s.scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("-o,--output", s.dir, "Sweep directory (results.csv, tables.md, runs/, figures); rerun to continue")
      ->required();
  cmd->add_option("--reference", s.reference,
                  "Reference EXR (default: path-trace one at --reference-spp into SWEEP_DIR/reference.exr)");
  cmd->add_option("--minutes", s.minutes, "Training-time budgets, comma-separated (default 1,2,5,10)")
      ->delimiter(',')
      ->check(positive_finite());
  cmd->add_option("--methods", s.methods, "Comma-separated: nr, isnr-kl, isnr-ikl (default nr,isnr-ikl)")
      ->delimiter(',');
  cmd->add_option("--samples", s.samples, "Incident directions per point N, comma-separated (default 4)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--seeds", s.seeds, "Seeds 1..K of every configuration (default 1)")->check(CLI::Range(1, 1000));
  cmd->add_option("--width", s.width, "Render width (default: the scene's film)")->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--height", s.height, "Render height (default: the scene's film)")->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--spp", s.render_spp, "Camera rays per pixel of the models' renders (default 16)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--reference-spp", s.reference_spp, "Samples per pixel of a reference the sweep path-traces (1024)")
      ->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--residual-points", s.residual_points, "Points of the residual metric (default 8192)")
      ->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--residual-samples", s.residual_samples, "Samples per point of the residual metric (default 64)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--path-tracing-cap", s.path_tracing_cap,
                  "The path tracer renders towards the best model's MAPE for at most this multiple of the largest "
                  "budget (default 4); beyond, its time is extrapolated")
      ->check(finite_in(0, 1000, true));
  cmd->add_option("--config", opt->config_file, "Training settings (JSON) for every run, as `train --config`");
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->sweep.scene_parameters);
  add_sensor_option(*cmd, opt->sweep.sensor);

  return {cmd, [opt]() {
            if (!opt->config_file.empty()) opt->sweep.base = radiosity::load_train_config(opt->config_file);
            opt->sweep.plot_script = plot_sweep_script();
            if (opt->sweep.plot_script.empty())
              std::fprintf(stderr,
                           "sweep: no figures: plot_sweep.py is not beside this binary (install it with `cmake "
                           "--install`); the tables are written as always\n");
            cl::Context ctx(cl::select_device(opt->device));
            sweep::run_sweep(ctx, opt->sweep);
            return 0;
          }};
}

}  // namespace clr::cli
