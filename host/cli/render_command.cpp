// clradiosity render SCENE.xml --model RUN_DIR -o OUT.exr [--spp S] [--png OUT.png] [--reference REF.exr]
//                   [--width W --height H] [--camera ox,oy,oz,tx,ty,tz,ux,uy,uz,fov]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "scene/fingerprint.hpp"

namespace clr::cli {

Command add_render_command(CLI::App& app) {
  struct Options {
    std::string scene, model, output, png, reference, error_map, device;
    std::vector<float> camera;
    radiosity::RenderSettings settings;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("render", "Render a scene from a trained model: Le + L_α at the first non-delta hit");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--model", opt->model, "Run directory written by `train` (or a model.clr file)")->required();
  cmd->add_option("-o,--output", opt->output, "Output image (EXR)")->required();
  cmd->add_option("--png", opt->png, "Also write a tonemapped sRGB PNG");
  cmd->add_option("--spp", opt->settings.spp, "Camera rays per pixel (default 4)")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--width", opt->settings.width, "Image width (default: the scene's film)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--height", opt->settings.height, "Image height (default: the scene's film)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--seed", opt->settings.seed, "Random seed of the camera rays")->check(integer_at_least(0));
  cmd->add_option("--camera", opt->camera,
                  "Another view: origin, target, up and vertical fov in degrees, as 10 comma-separated numbers")
      ->delimiter(',')
      ->expected(10)
      ->check(finite_number());
  cmd->add_option("--reference", opt->reference, "Print MAPE/MSE/relMSE against this EXR and write an error map");
  cmd->add_option("--error-map", opt->error_map, "Error map path (default: OUT with _error.png)");
  add_device_option(*cmd, opt->device);

  return {cmd, [opt]() {
            if (!opt->reference.empty() && opt->error_map.empty())
              opt->error_map = std::filesystem::path(opt->output).replace_extension().string() + "_error.png";
            auto scene = scene::load_scene(opt->scene);
            auto inputs = radiosity::RunDirectory::input_files(opt->model);
            inputs.insert(inputs.end(), scene.files.begin(), scene.files.end());
            inputs.push_back(opt->reference);
            require_outputs({{opt->output, "-o"}, {opt->png, "--png"}, {opt->error_map, "--error-map"}}, inputs);
            radiosity::RunDirectory::require_scene(opt->model, scene::fingerprint(scene));
            if (opt->camera.empty()) scene::require_sensor(scene, opt->scene);
            if (!opt->camera.empty()) {
              const auto& c = opt->camera;
              const glm::vec3 origin(c[0], c[1], c[2]), target(c[3], c[4], c[5]), up(c[6], c[7], c[8]);
              if (glm::length(target - origin) <= 0 || glm::length(glm::cross(target - origin, up)) <= 0 ||
                  !(c[9] > 0 && c[9] < 180))
                throw InputError(
                    "--camera: origin and target must differ, up must not be parallel to the view, "
                    "and fov must be in (0, 180)");
              // Mitsuba's look-at frame: +z towards the target, +x = up × z (to the image's left).
              const glm::vec3 z = glm::normalize(target - origin), x = glm::normalize(glm::cross(up, z));
              scene.camera.to_world =
                  glm::mat4(glm::vec4(x, 0), glm::vec4(glm::cross(z, x), 0), glm::vec4(z, 0), glm::vec4(origin, 1));
              scene.camera.fov_degrees = c[9];
              scene.camera.fov_axis = scene::Camera::FovAxis::y;
              scene.camera.projection = scene::Camera::Projection::perspective;
              scene.camera.aperture_radius = 0;
              scene.camera.validate("--camera");
            }
            // The model's renderer traces pinhole rays; depth of field is the reference's alone.
            if (scene.camera.aperture_radius > 0)
              throw InputError(opt->scene +
                               ": a thinlens sensor is rendered by `reference` only (give --camera to render a "
                               "pinhole view of the model)");
            const geometry::Geometry geometry(scene);
            cl::Context ctx(cl::select_device(opt->device));
            auto network = radiosity::RunDirectory::load_radiance(ctx, opt->model);
            // A reference that cannot be read fails before the render, not after it.
            std::optional<image::Image> reference;
            if (!opt->reference.empty()) reference = image::read_exr(opt->reference);
            const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx, *network), opt->settings);
            image::write_exr(opt->output, img);
            if (!opt->png.empty()) image::write_png(opt->png, img);
            std::cout << "image: " << opt->output << (opt->png.empty() ? "" : ", " + opt->png) << "\n";
            if (reference) {
              const auto ref = image::match_size(*reference, img);
              const auto m = image::compare(img, ref);
              image::write_png(opt->error_map, image::error_map(img, ref));
              std::printf("%s  (error map: %s)\n", image::describe(m).c_str(), opt->error_map.c_str());
            }
            return 0;
          }};
}

}  // namespace clr::cli
