// clradiosity reference SCENE.xml --spp N [--width W --height H] [--max-depth D] [--seed K] -o OUT.exr
#include <cstdio>
#include <iostream>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "distributed/image_rows.hpp"
#include "geometry/geometry.hpp"
#include "image/image_format.hpp"
#include "reference/path_tracer.hpp"
#include "scene/fingerprint.hpp"

namespace clr::cli {

Command add_reference_command(CLI::App& app) {
  struct Options {
    std::string scene, output;
    std::map<std::string, std::string> parameters;
    int sensor = 0;
    reference::RenderOptions render;
  };
  auto opt = std::make_shared<Options>();
  opt->render.progress = true;
  opt->render.spp = 0;  // the scene's sampler's, unless --spp
  auto* cmd = app.add_subcommand("reference", "Render a path-traced reference image (CPU, all cores)");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--spp", opt->render.spp, "Samples per pixel (default: the scene's <sampler> sample_count)")
      ->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--width", opt->render.width, "Image width (default: the scene's film)")->check(CLI::Range(1, 65536));
  cmd->add_option("--height", opt->render.height, "Image height (default: the scene's film)")
      ->check(CLI::Range(1, 65536));
  cmd->add_option_function<int>(
         "--max-depth", [opt](const int& d) { opt->render.max_depth = d; },
         "Longest path in segments; -1: unbounded (default: the scene integrator's max_depth, else -1)")
      ->check(CLI::Range(-1, 1 << 20));
  cmd->add_option("--seed", opt->render.seed, "Random seed")->check(integer_at_least(0));
  add_threads_option(*cmd);
  add_scene_parameters_option(*cmd, opt->parameters);
  add_sensor_option(*cmd, opt->sensor);
  cmd->add_option("-o,--output", opt->output, "Output image: .exr (linear) or .png (sRGB), by its extension")
      ->required();

  return {
      cmd, [opt]() {
        // Under mpirun the ranks share the rows and rank 0 alone writes the image.
        const auto& ranks = distributed::Communicator::world();
        const auto format = image::output_format(opt->output, "-o");
        const scene::Scene scene = scene::load_scene(opt->scene, opt->parameters, opt->sensor);
        ranks.require_same("the scenes (the contents of their files)",
                           Digest().add(scene::fingerprint(scene).digest).value());
        if (ranks.rank() == 0) require_outputs({{opt->output, "-o"}}, scene.files);
        scene::require_sensor(scene, opt->scene);
        opt->render.spp = reference::samples_per_pixel(scene, opt->scene, opt->render.spp, "--spp");
        scene::require_emitter(scene, opt->scene);
        const geometry::Geometry geometry(scene);
        reference::RenderStats stats;
        opt->render.row_offset = ranks.rank();
        opt->render.row_stride = ranks.size();
        const auto img = distributed::gather_interleaved_rows(ranks, reference::render(geometry, opt->render, &stats));
        double totals[] = {double(stats.paths), double(stats.rays), double(stats.non_finite)};
        ranks.sum(totals);
        stats.paths = std::uint64_t(totals[0]);
        stats.rays = std::uint64_t(totals[1]);
        stats.non_finite = std::uint64_t(totals[2]);
        stats.seconds = ranks.max(stats.seconds);
        if (ranks.rank() != 0) return 0;
        image::write_image(
            opt->output, img, format,
            exr_metadata(scene::fingerprint(scene).digest, opt->render.spp, opt->render.seed, stats.seconds));
        std::printf(
            "%s: %dx%d, %d spp, %.3f s, %.2f Msamples/s, %.2f Mrays/s%s\n", opt->output.c_str(), img.width, img.height,
            opt->render.spp, stats.seconds, double(stats.paths) / stats.seconds * 1e-6,
            double(stats.rays) / stats.seconds * 1e-6,
            stats.non_finite ? (", " + std::to_string(stats.non_finite) + " non-finite samples dropped").c_str() : "");
        return 0;
      }};
}

}  // namespace clr::cli
