// clradiosity report RUN_DIR -o REPORT.html [--reference REF.exr] [--scene SCENE.xml] [--spp S]
//                    [--model-image M.exr] [--path-tracer-image P.exr | --no-path-tracer]
//                    [--path-tracer-seconds T] [--path-tracer-max-spp N]
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "radiosity/run_directory.hpp"
#include "report/folder_report.hpp"

namespace clr::cli {

void write_run_report(const report::RunReportOptions& options, const std::filesystem::path& out) {
  const auto data = report::folder_report(options);
  const auto start = std::chrono::steady_clock::now();
  const std::string page = report::report_html(data);
  // Atomically: an interrupted or failed write never leaves a page that looks complete.
  write_text_atomically(out, page);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& img : data.images)
    if (img.metrics) std::printf("%s: %s\n", img.title.c_str(), image::describe(*img.metrics).c_str());
  std::printf("report: %s (%.1f MB, written in %.2f s)\n", out.c_str(), double(page.size()) / 1e6, seconds);
}

Command add_report_command(CLI::App& app) {
  struct Options {
    report::RunReportOptions run;
    std::string run_dir, out, reference, scene, model_image, path_tracer_image;
    bool no_path_tracer = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("report",
                                 "One self-contained HTML page of a run: its images compared with the reference and "
                                 "the path tracer, its convergence, its record");
  cmd->add_option(
         "run", opt->run_dir,
         "Run directory written by `train`, a sweep folder (`sweep`) or a paper-tables folder (bench/paper_tables.sh)")
      ->required();
  cmd->add_option("-o", opt->out, "Output page (.html)")->required();
  cmd->add_option("--reference", opt->reference,
                  "The reference EXR (default: TungstenRender.exr beside the run's scene, where the run's "
                  "evaluation.json records its pixels)");
  cmd->add_option("--scene", opt->scene, "The run's scene (default: the file its scene.json records)");
  cmd->add_option("--spp", opt->run.spp,
                  "Camera rays a pixel of the model's render (default: the run's evaluations', "
                  "else 4)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--model-image", opt->model_image,
                  "The model's render (EXR at the reference's size) instead of "
                  "rendering it");
  auto* pt_image = cmd->add_option("--path-tracer-image", opt->path_tracer_image,
                                   "The path tracer's image (EXR at the reference's size) instead of rendering it");
  cmd->add_flag("--no-path-tracer", opt->no_path_tracer, "Leave the path tracer out")->excludes(pt_image);
  cmd->add_option("--path-tracer-seconds", opt->run.path_tracer_seconds,
                  "The path tracer's time (default: the run's training seconds)")
      ->check(finite_in(0, 1e7, true));
  cmd->add_option("--path-tracer-max-spp", opt->run.path_tracer_max_spp,
                  "At most this many samples a pixel for the path tracer (default 1024)")
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--guide-grid", opt->run.guide_grid,
                  "ISNR runs: the I-Module's lobes beside their target at G x G pixels, precomputed (default 6; 0: "
                  "none)")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--guide-resolution", opt->run.guide_resolution,
                  "Rows of each guide map (twice as many columns; default 32)")
      ->check(CLI::Range(8, 2048));
  add_device_option(*cmd, opt->run.device);
  add_sensor_option(*cmd, opt->run.sensor);

  return {cmd, [opt]() {
            const std::filesystem::path out = opt->out;
            report::require_report_path(out, "-o");
            auto inputs = std::filesystem::is_directory(opt->run_dir)
                              ? radiosity::RunDirectory::input_files(opt->run_dir)
                              : std::vector<std::filesystem::path>{};
            inputs.insert(inputs.end(), {opt->reference, opt->model_image, opt->path_tracer_image, opt->scene});
            require_outputs({{out, "-o"}}, inputs);
            opt->run.run = opt->run_dir;
            opt->run.reference = opt->reference;
            opt->run.scene = opt->scene;
            opt->run.model_image = opt->model_image;
            opt->run.path_tracer_image = opt->path_tracer_image;
            opt->run.path_tracer = !opt->no_path_tracer;
            write_run_report(opt->run, out);
            return 0;
          }};
}

}  // namespace clr::cli
