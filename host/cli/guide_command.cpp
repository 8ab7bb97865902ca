// clradiosity guide SCENE.xml --model RUN_DIR --pixel X,Y -o OUT.png [--width W --height H] [--resolution R]
//                  [--exr OUT.exr]
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "image/image_format.hpp"
#include "radiosity/guide/guide_view.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "scene/fingerprint.hpp"

namespace clr::cli {
namespace {

// q beside the target, a 4-pixel gap between: densities × 4π (1 = uniform) on a log scale from 10⁻² to 10², one
// scale for both so that they compare.
image::Image side_by_side(const radiosity::GuideView& v, bool log_scale) {
  const int w = v.q.width, h = v.q.height, gap = 4;
  image::Image out(2 * w + gap, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int panel = 0; panel < 2; ++panel) {
        const float d = (panel == 0 ? v.q : v.target).pixel(x, y)[0];
        const float shown =
            log_scale ? std::clamp((std::log10(std::max(d * 4.0f * float(M_PI), 1e-30f)) + 2.0f) / 4.0f, 0.0f, 1.0f)
                      : d;
        float* p = out.pixel(x + panel * (w + gap), y);
        p[0] = p[1] = p[2] = shown;
      }
  return out;
}

}  // namespace

Command add_guide_command(CLI::App& app) {
  struct Options {
    std::string scene, model, output, exr, device;
    std::map<std::string, std::string> parameters;
    int sensor = 0;
    std::vector<float> pixel;
    int width = 0, height = 0, resolution = 128;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "guide", "Show what an ISNR run's I-Module learned at the surface seen through a pixel: q beside its target");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--model", opt->model, "Run directory written by `train --method isnr`")->required();
  cmd->add_option("--pixel", opt->pixel, "Pixel X,Y of the width × height image")
      ->delimiter(',')
      ->expected(2)
      ->required();
  cmd->add_option("-o,--output", opt->output,
                  "Lat-long maps about the normal, q (left) and the target f·cos·L_i/F (right): .png on one log scale, "
                  ".exr as densities per steradian")
      ->required();
  cmd->add_option("--exr", opt->exr, "Also write both maps as densities per steradian (EXR)");
  cmd->add_option("--width", opt->width, "Image width the pixel refers to (default: the scene's film)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--height", opt->height, "Image height (default: the scene's film)")->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--resolution", opt->resolution, "Rows of each lat-long map (default 128; twice as many columns)")
      ->check(CLI::Range(8, 2048));
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->parameters);
  add_sensor_option(*cmd, opt->sensor);

  return {cmd, [opt]() {
            const auto format = image::output_format(opt->output, "-o", {image::Format::Png, image::Format::Exr});
            image::output_format(opt->exr, "--exr", {image::Format::Exr});
            const auto scene = scene::load_scene(opt->scene, opt->parameters, opt->sensor);
            const int width = opt->width > 0 ? opt->width : scene.camera.width;
            const int height = opt->height > 0 ? opt->height : scene.camera.height;
            const float px = opt->pixel[0], py = opt->pixel[1];
            if (!(px >= 0 && px < float(width) && py >= 0 && py < float(height)))
              throw InputError("--pixel " + nlohmann::json(px).dump() + "," + nlohmann::json(py).dump() +
                               " is outside the " + std::to_string(width) + "×" + std::to_string(height) + " image");
            auto inputs = radiosity::RunDirectory::input_files(opt->model);
            inputs.insert(inputs.end(), scene.files.begin(), scene.files.end());
            require_outputs({{opt->output, "-o"}, {opt->exr, "--exr"}}, inputs);
            radiosity::RunDirectory::require_scene(opt->model, scene::fingerprint(scene));
            const geometry::Geometry geometry(scene);
            cl::Context ctx(cl::select_device(opt->device));
            const std::filesystem::path run = opt->model;
            auto radiance = radiosity::RunDirectory::load_radiance(ctx, run);
            auto guide = radiosity::RunDirectory::load_guide(ctx, run);
            const auto view = radiosity::view_guide(ctx, geometry, *radiance, *guide, std::floor(px) + 0.5f,
                                                    std::floor(py) + 0.5f, width, height, opt->resolution);
            // A PNG shows both maps on one log scale; an EXR holds them as densities (what --exr writes).
            auto metadata = exr_metadata(scene::fingerprint(scene).digest, std::nullopt, std::nullopt, std::nullopt,
                                         static_cast<long long>(radiance->steps()));
            char pixel[64];
            std::snprintf(pixel, sizeof pixel, "%g,%g", double(px), double(py));
            metadata["pixel"] = pixel;
            image::write_image(opt->output, side_by_side(view, format == image::Format::Png), format, metadata);
            if (!opt->exr.empty()) image::write_exr(opt->exr, side_by_side(view, false), metadata);
            std::printf(
                "guide: %s%s  KL(p||q) %.4g  q's mass where the target is lit %.4g  (lit: %.4g of the sphere)\n",
                opt->output.c_str(), opt->exr.empty() ? "" : (", " + opt->exr).c_str(), view.kl, view.q_mass_lit,
                view.lit_fraction);
            return 0;
          }};
}

}  // namespace clr::cli
