// clradiosity reference SCENE.xml --spp N [--width W --height H] [--max-depth D] [--seed K] -o OUT.exr [--resume]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "common/terminal_text.hpp"
#include "distributed/image_rows.hpp"
#include "geometry/geometry.hpp"
#include "image/image_format.hpp"
#include "reference/path_tracer.hpp"
#include "scene/fingerprint.hpp"
#include "scene/reference_record.hpp"

namespace clr::cli {
namespace {

// The image `path` holds of an earlier render with `wanted`'s identity, and its spp and seconds; InputError naming
// what differs where it is not one.
struct Earlier {
  image::Image mean;
  int spp = 0;
  double seconds = 0;
};
Earlier read_earlier(const std::string& path, const std::map<std::string, std::string>& wanted) {
  std::map<std::string, std::string> attributes;
  Earlier e;
  e.mean = image::read_exr(path, &attributes);
  attributes["size"] = std::to_string(e.mean.width) + "x" + std::to_string(e.mean.height);
  const auto refuse = [&](const std::string& why) {
    throw InputError("--resume: " + path + " " + why +
                     "; resume it with the command that made it, or write to another -o");
  };
  const auto spp = attributes.find("spp");
  if (!attributes.contains("software") || !attributes["software"].starts_with("clradiosity") ||
      spp == attributes.end() || !attributes.contains("maxDepth"))
    refuse("is not an image of clradiosity reference (its EXR header has no spp and maxDepth)");
  for (const auto& [key, value] : wanted)
    if (attributes[key] != value)
      refuse("is another render: its " + key + " is '" + attributes[key] + "', this command's '" + value + "'");
  try {
    std::size_t end = 0;
    e.spp = std::stoi(spp->second, &end);
    if (end != spp->second.size() || e.spp < 1) throw std::invalid_argument("spp");
    e.seconds = attributes.contains("renderTimeSeconds") ? std::stod(attributes["renderTimeSeconds"]) : 0.0;
    if (!std::isfinite(e.seconds) || e.seconds < 0) throw std::invalid_argument("time");
  } catch (const std::logic_error&) {
    refuse("records no usable spp or time");
  }
  // The mean the new passes are averaged with: a pixel that is not a finite radiance ≥ 0 was not made by a render
  // (an edited file), and would poison or skew every pass it is averaged with.
  if (!std::all_of(e.mean.rgb.begin(), e.mean.rgb.end(), [](float v) { return std::isfinite(v) && v >= 0; }))
    refuse("holds pixels that are not finite radiances ≥ 0 (NaN, infinite or negative)");
  return e;
}

}  // namespace

Command add_reference_command(CLI::App& app) {
  struct Options {
    std::string scene, output;
    std::map<std::string, std::string> parameters;
    int sensor = 0;
    bool resume = false;
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
  cmd->add_flag("--resume", opt->resume,
                "Continue OUT.exr, an earlier render of this command (same scene, sensor, size, depth, seed): draw "
                "only the samples it lacks up to --spp. A render that Ctrl-C stopped keeps its finished passes");

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
        const int max_depth = opt->render.max_depth.value_or(scene.max_depth);
        // What becomes of an integrator the path tracer does not implement, unless --max-depth decides the image.
        if (!scene.integrator_note.empty() && !opt->render.max_depth && ranks.rank() == 0 && !Progress::silenced())
          std::fprintf(stderr, "%s\n", terminal_safe(scene.integrator_note).c_str());
        const std::string digest = scene::fingerprint(scene).digest;
        const auto wanted = scene::reference_record(digest, scene.camera.resized(opt->render.width, opt->render.height),
                                                    opt->sensor, max_depth, opt->render.seed);
        // A stop keeps the finished passes (a few samples per pixel each) in one process; ranks would each stop after
        // another pass, so under mpirun a stop ends the job as it ends any.
        opt->render.stoppable = !ranks.distributed();
        Earlier earlier;
        if (opt->resume) {
          if (ranks.distributed())
            throw distributed::JobInputError("--resume runs in one process: start it without mpirun");
          if (format != image::Format::Exr)
            throw InputError("--resume: -o " + opt->output + " must be an .exr (a .png keeps 8 bits, not the sums)");
          if (std::filesystem::exists(opt->output)) earlier = read_earlier(opt->output, wanted);
          if (earlier.spp >= opt->render.spp) {
            std::printf("%s: already has %d spp (--spp %d): left as it is\n", opt->output.c_str(), earlier.spp,
                        opt->render.spp);
            return 0;
          }
          if (earlier.spp > 0 && !Progress::silenced())
            std::fprintf(stderr, "%s: %d spp so far; adding %d\n", opt->output.c_str(), earlier.spp,
                         opt->render.spp - earlier.spp);
          opt->render.first_sample = earlier.spp;
          opt->render.spp -= earlier.spp;
        }
        if (opt->render.stoppable) install_stop_handlers();
        reference::RenderStats stats;
        opt->render.between_passes = [&ranks] { ranks.keep_alive(); };
        opt->render.row_offset = ranks.rank();
        opt->render.row_stride = ranks.size();
        auto img = distributed::gather_interleaved_rows(ranks, reference::render(geometry, opt->render, &stats));
        double totals[] = {double(stats.paths), double(stats.rays), double(stats.non_finite)};
        ranks.sum(totals);
        stats.paths = std::uint64_t(totals[0]);
        stats.rays = std::uint64_t(totals[1]);
        stats.non_finite = std::uint64_t(totals[2]);
        stats.seconds = ranks.max(stats.seconds);
        if (ranks.rank() != 0) return 0;
        const int spp = earlier.spp + stats.spp;
        if (stats.spp == 0) {  // stopped before a pass ended: nothing new to keep
          std::fprintf(stderr, "%s: stopped before its first pass ended; nothing written\n", opt->output.c_str());
          return 0;
        }
        if (earlier.spp > 0)  // the spp-weighted mean of both renders
          for (std::size_t i = 0; i < img.rgb.size(); ++i)
            img.rgb[i] = float((double(earlier.mean.rgb[i]) * earlier.spp + double(img.rgb[i]) * stats.spp) / spp);
        auto metadata = exr_metadata(digest, spp, opt->render.seed, earlier.seconds + stats.seconds);
        metadata.insert(wanted.begin(), wanted.end());
        image::write_image(opt->output, img, format, metadata);
        std::string note;
        if (stats.non_finite) note += ", " + std::to_string(stats.non_finite) + " non-finite samples dropped";
        if (stats.spp < opt->render.spp)
          note += "; stopped after " + std::to_string(spp) + " of " + std::to_string(earlier.spp + opt->render.spp) +
                  " spp (--resume adds the rest)";
        std::printf("%s: %dx%d, %d spp, %.3f s, %.2f Msamples/s, %.2f Mrays/s%s\n", opt->output.c_str(), img.width,
                    img.height, spp, stats.seconds, double(stats.paths) / stats.seconds * 1e-6,
                    double(stats.rays) / stats.seconds * 1e-6, note.c_str());
        return 0;
      }};
}

}  // namespace clr::cli
