// clradiosity render SCENE.xml --model RUN_DIR -o OUT.exr [--spp S] [--png OUT.png] [--reference REF.exr]
//                   [--width W --height H] [--camera ox,oy,oz,tx,ty,tz,ux,uy,uz,fov]
// clradiosity render SCENE.xml --model RUN_DIR (--path PATH.json | --orbit N) -o FRAMES_DIR [--png] [--video V.mp4]
//                   [--fps F] [--path-tracer-check K [--check-spp S]]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/run_lock.hpp"
#include "common/stop_signal.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "image/image_format.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "scene/fingerprint.hpp"
#include "scene/reference_record.hpp"
#include "scene/sensors/camera_path.hpp"
#include "walkthrough/break_even.hpp"
#include "walkthrough/frame_sequence.hpp"
#include "walkthrough/video.hpp"

namespace clr::cli {
namespace {

struct Options {
  std::string scene, model, output, png, reference, error_map, device, path, video;
  std::map<std::string, std::string> parameters;
  int sensor = 0;
  int orbit = 0, path_tracer_check = 0, check_spp = 1024;
  double fps = 30;
  std::vector<float> camera;
  radiosity::RenderSettings settings;
  bool png_given = false;
};

// The frames of a camera path into FRAMES_DIR (walkthrough/), then the video and the break-even check.
int render_walkthrough(const Options& opt, const scene::Scene& scene, const geometry::Geometry& geometry) {
  scene::require_sensor(scene, opt.scene);
  const auto cameras = opt.path.empty() ? scene::orbit(scene.camera, scene::geometry_centre(scene.shapes), opt.orbit)
                                        : scene::read_camera_path(opt.path, scene.camera);
  if (!opt.video.empty()) walkthrough::require_video_writer(opt.video);
  // What the break-even check needs is checked before any frame is rendered: the run's training time (a model
  // without a log, or a log without a training row, has none, and every frame count would be meaningless) and a
  // frame count the path has.
  double training_seconds = 0;
  if (opt.path_tracer_check > 0) {
    if (std::size_t(opt.path_tracer_check) > cameras.size())
      throw InputError("--path-tracer-check " + std::to_string(opt.path_tracer_check) + ": the path has only " +
                       std::to_string(cameras.size()) + " frames");
    if (!std::filesystem::is_directory(opt.model))
      throw InputError("--path-tracer-check: --model " + opt.model +
                       " is a model file; the check needs its run directory (its log holds the training time)");
    training_seconds = radiosity::RunDirectory::training_seconds(opt.model);
    if (!(training_seconds > 0))
      throw InputError("--path-tracer-check: the log of " + opt.model +
                       " records no training time (no row yet): there is no cost to break even with");
  }
  std::filesystem::create_directories(opt.output);
  const RunLock lock(opt.output);  // one render per FRAMES_DIR
  install_stop_handlers();
  cl::Context ctx(cl::select_device(opt.device));
  auto network = radiosity::RunDirectory::load_radiance(ctx, opt.model);
  const auto field = radiosity::radiance_query(ctx, *network);

  walkthrough::SequenceOptions seq;
  seq.dir = opt.output;
  seq.png = opt.png_given || !opt.video.empty();  // the video is made from the PNGs
  seq.settings = opt.settings;
  seq.exr_attributes = exr_metadata(scene::fingerprint(scene).digest, opt.settings.spp, opt.settings.seed, std::nullopt,
                                    static_cast<long long>(network->steps()));
  seq.record = {{"scene", scene::fingerprint(scene).digest},
                {"model", Digest().add_file(radiosity::RunDirectory::input_files(opt.model).front()).hex()}};
  const auto done = walkthrough::render_sequence(geometry, cameras, field, seq);
  std::printf("frames: %s, %zu rendered now (%.3f s per frame), %zu from an earlier run\n", opt.output.c_str(),
              done.rendered, done.rendered ? done.seconds / double(done.rendered) : 0.0, done.reused);
  if (!done.complete) {
    std::printf("render: stopped; the finished frames are kept — run the same command again to continue\n");
    return 0;
  }
  if (!opt.video.empty()) {
    if (!walkthrough::write_video(opt.output, cameras.size(), opt.fps, opt.video)) {
      std::printf("render: stopped while the video was written; the frames are kept\n");
      return 0;
    }
    std::printf("video: %s (%zu frames at %g fps)\n", opt.video.c_str(), cameras.size(), opt.fps);
  }
  if (opt.path_tracer_check > 0) {
    walkthrough::BreakEvenOptions check;
    check.frames_checked = opt.path_tracer_check;
    check.reference_spp = opt.check_spp;
    check.settings = opt.settings;
    check.training_seconds = training_seconds;
    // The path's own throughput, where this process rendered it: more frames, a steadier figure than K.
    if (done.rendered > 0) check.model_seconds_per_frame = done.seconds / double(done.rendered);
    const auto b = walkthrough::measure_break_even(geometry, cameras, field, check);
    if (stop_requested()) {
      std::printf("render: stopped during the break-even check; the frames are kept, no figures were written\n");
      return 0;
    }
    for (const auto& c : b.checks)
      std::printf("frame %zu: model MAPE %.4f; path tracer %.2f s to reach it (%d spp measured%s)\n", c.frame,
                  c.model_mape, c.path_tracer_seconds, c.path_tracer_spp, c.extrapolated ? ", extrapolated" : "");
    std::printf(
        "break-even: model %.3f s/frame, path tracer %.2f s/frame at equal error, training %.0f s → the model is "
        "cheaper after %s frames\n",
        b.model_seconds_per_frame, b.path_tracer_seconds_per_frame, b.training_seconds,
        std::isfinite(b.frames) ? std::to_string(long(std::ceil(b.frames))).c_str() : "no number of");
    const auto file = std::filesystem::path(opt.output) / "break_even.json";
    write_text_atomically(file, b.to_json().dump(2) + "\n");
    std::printf("break-even figures: %s\n", file.c_str());
  }
  return 0;
}

int render_image(Options& opt, scene::Scene& scene) {
  if (opt.camera.empty()) scene::require_sensor(scene, opt.scene);
  if (!opt.camera.empty()) scene.camera = scene.camera.pinhole_view(opt.camera, "--camera");
  // The model's renderer traces pinhole rays; depth of field is the reference's alone.
  if (scene.camera.aperture_radius > 0)
    throw InputError(opt.scene +
                     ": a thinlens sensor is rendered by `reference` only (give --camera to render a pinhole view of "
                     "the model)");
  const geometry::Geometry geometry(scene);
  cl::Context ctx(cl::select_device(opt.device));
  auto network = radiosity::RunDirectory::load_radiance(ctx, opt.model);
  // A reference that cannot be read fails before the render, not after it.
  std::optional<image::Image> reference;
  if (!opt.reference.empty()) {
    std::map<std::string, std::string> attributes;
    reference = image::read_exr(opt.reference, &attributes);
    image::require_usable_reference(*reference, "--reference " + opt.reference);
    // Recorded references of another scene or sensor are refused; a --camera view is no sensor's.
    if (const std::string warning =
            scene::check_reference_record(attributes, scene::fingerprint(scene).digest,
                                          opt.camera.empty() ? opt.sensor : -1, "--reference", opt.reference);
        !warning.empty() && !Progress::silenced())
      std::cerr << "render: warning: " << warning << "\n";
    const scene::Camera view = scene.camera.resized(opt.settings.width, opt.settings.height);
    try {
      image::require_matching_size(reference->width, reference->height, view.width, view.height);
    } catch (const InputError& e) {
      throw InputError("--reference " + opt.reference + ": " + e.what());
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx, *network), opt.settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  image::write_image(opt.output, img, image::output_format(opt.output, "-o"),
                     exr_metadata(scene::fingerprint(scene).digest, opt.settings.spp, opt.settings.seed, seconds,
                                  static_cast<long long>(network->steps())));
  if (!opt.png.empty()) image::write_png(opt.png, img);
  std::cout << "image: " << opt.output << (opt.png.empty() ? "" : ", " + opt.png) << "\n";
  if (reference) {
    const auto ref = image::match_size(*reference, img);
    const auto m = image::compare(img, ref);
    image::write_png(opt.error_map, image::error_map(img, ref));
    std::printf("%s  (error map: %s)\n", image::describe(m).c_str(), opt.error_map.c_str());
  }
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("render", "Render a scene from a trained model: Le + L_α at the first non-delta hit");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--model", opt->model, "Run directory written by `train` (or a model.clr file)")->required();
  cmd->add_option("-o,--output", opt->output,
                  "Output image (.exr or .png, by its extension), or with --path/--orbit the frames' folder")
      ->required();
  cmd->add_option("--png", opt->png, "Also write a tonemapped sRGB PNG (with --path/--orbit: a flag, one per frame)")
      ->expected(0, 1);
  cmd->add_option("--spp", opt->settings.spp, "Camera rays per pixel (default 4)")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--mode", opt->settings.mode,
                  "lhs (default): the model's radiance where the camera ray lands; rhs: one more bounce there (the "
                  "direct light by next-event estimation, one BSDF sample, the model where it lands), the Neural "
                  "Radiosity authors' RHS image")
      ->transform(CLI::CheckedTransformer(radiosity::render_mode_names()));
  cmd->add_option("--width", opt->settings.width, "Image width (default: the scene's film)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--height", opt->settings.height, "Image height (default: the scene's film)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--seed", opt->settings.seed, "Random seed of the camera rays")->check(integer_at_least(0));
  auto* camera = cmd->add_option("--camera", opt->camera,
                                 "Another view: origin, target, up and vertical fov in degrees, as 10 comma-separated "
                                 "numbers")
                     ->delimiter(',')
                     ->expected(10)
                     ->check(finite_number());
  auto* reference =
      cmd->add_option("--reference", opt->reference, "Print MAPE/MSE/relMSE against this EXR and write an error map");
  auto* error_map = cmd->add_option("--error-map", opt->error_map, "Error map path (default: OUT with _error.png)");
  auto* path = cmd->add_option("--path", opt->path,
                               "A camera path (JSON keyframes, docs/walkthrough.md): its frames into the folder -o, "
                               "back to back; a rerun renders the missing ones");
  auto* orbit = cmd->add_option("--orbit", opt->orbit, "N frames around the scene's centre from the sensor's view")
                    ->check(CLI::Range(1, 100000))
                    ->excludes(path);
  for (auto* frames : {path, orbit}) frames->excludes(camera)->excludes(reference)->excludes(error_map);
  auto* video = cmd->add_option("--video", opt->video,
                                "With --path/--orbit: also a video of the frames (.mp4, "
                                ".webm or .gif; needs ffmpeg)");
  cmd->add_option("--fps", opt->fps, "The video's frames per second (default 30)")
      ->check(finite_in(0, 1000, true))
      ->needs(video);
  auto* check = cmd->add_option("--path-tracer-check", opt->path_tracer_check,
                                "With --path/--orbit: path-trace K evenly spaced frames to the model's error and print "
                                "the frame count after which training pays for itself")
                    ->check(CLI::Range(1, 1000));
  cmd->add_option("--check-spp", opt->check_spp, "Samples per pixel of the checked frames' references (1024)")
      ->check(CLI::Range(1, 1 << 20))
      ->needs(check);
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->parameters);
  add_sensor_option(*cmd, opt->sensor);

  return {cmd, [opt, cmd]() {
            const bool frames = !opt->path.empty() || cmd->count("--orbit") > 0;
            opt->png_given = cmd->count("--png") > 0;
            if (!frames && (!opt->video.empty() || opt->path_tracer_check > 0))
              throw InputError(std::string(opt->video.empty() ? "--path-tracer-check" : "--video") +
                               " needs a camera path: --path PATH.json or --orbit N");
            if (!frames && opt->png_given && opt->png.empty())
              throw InputError("--png needs a file name (a flag only with --path or --orbit)");
            if (frames && !opt->png.empty())
              throw InputError("--png takes no file name with --path or --orbit (each frame gets its PNG)");
            if (!opt->reference.empty() && opt->error_map.empty())
              opt->error_map = std::filesystem::path(opt->output).replace_extension().string() + "_error.png";
            if (!frames) image::output_format(opt->output, "-o");
            image::output_format(opt->png, "--png", {image::Format::Png});
            image::output_format(opt->error_map, "--error-map", {image::Format::Png});
            auto scene = scene::load_scene(opt->scene, opt->parameters, opt->sensor);
            auto inputs = radiosity::RunDirectory::input_files(opt->model);
            inputs.insert(inputs.end(), scene.files.begin(), scene.files.end());
            inputs.insert(inputs.end(), {opt->reference, opt->path});
            require_outputs({{frames ? std::string() : opt->output, "-o"},
                             {opt->png, "--png"},
                             {opt->error_map, "--error-map"},
                             {opt->video, "--video"}},
                            inputs);
            radiosity::RunDirectory::require_scene(opt->model, scene::fingerprint(scene));
            if (!frames) return render_image(*opt, scene);
            if (scene.camera.aperture_radius > 0)
              throw InputError(opt->scene + ": a thinlens sensor is rendered by `reference` only");
            const geometry::Geometry geometry(scene);
            return render_walkthrough(*opt, scene, geometry);
          }};
}

}  // namespace clr::cli
