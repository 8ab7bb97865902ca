// `clradiosity` without arguments: the bundled Cornell box end to end on the default device. Trains for a short
// fixed budget (or a preset's), renders at the scene's 128×128, renders a path-traced reference (cached beside the
// run), and prints where the images are and the MAPE between them.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/data_files.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/run_lock.hpp"
#include "common/stop_signal.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/preset.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/fingerprint.hpp"
#include "scene/scene.hpp"

namespace clr::cli {
namespace fs = std::filesystem;

int run_main_job(double minutes, const std::string& preset) {
  const fs::path scene_path = bundled_scenes_dir() / "cornell-box.xml";
  const fs::path out = fs::absolute("clradiosity-out");
  const fs::path run = out / "cornell-box-run";
  // One main job per folder: a second one would delete the first's run below while it trains.
  const RunLock out_lock(out);
  const auto scene = scene::load_scene(scene_path);
  const geometry::Geometry geometry(scene);
  cl::Context ctx(cl::select_device(""));
  radiosity::TrainConfig config;
  if (preset.empty()) {
    config.minutes = minutes;
  } else {
    const geometry::SurfaceSampler sampler(scene);
    for (const auto& line :
         radiosity::apply_preset(preset, config, radiosity::scene_inputs(geometry, sampler), ctx.device()))
      if (!Progress::silenced()) std::cerr << "preset " << preset << ": " << line << "\n";
  }
  if (!Progress::silenced())
    std::cerr << "clradiosity: training " << scene_path.string() << " for " << config.minutes << " min on "
              << ctx.device().describe() << "\n";

  // The reference depends only on the scene, its pixel filter and these settings, so it is rendered once and
  // reused; one that no longer fits (another size, another filter — one made before the filter was recorded —
  // unreadable) is found before training, not after it, and made again.
  const fs::path ref_path = out / "cornell-box-reference-1024spp.exr";
  const std::string filter = scene.camera.filter.describe();
  if (fs::exists(ref_path)) {
    try {
      std::map<std::string, std::string> attributes;
      const auto kept = image::read_exr(ref_path, &attributes);
      image::require_matching_size(kept.width, kept.height, scene.camera.width, scene.camera.height);
      if (attributes["pixelFilter"] != filter) fs::remove(ref_path);
    } catch (const InputError&) {
      fs::remove(ref_path);
    }
  }

  fs::remove_all(run);
  radiosity::Trainer trainer(ctx, geometry, config, run, false);
  trainer.run();
  if (stop_requested()) return 0;  // the first Ctrl-C ends the whole job: no render, no reference

  radiosity::RenderSettings settings;
  settings.spp = 16;
  const std::string digest = scene::fingerprint(scene).digest;
  const auto start = std::chrono::steady_clock::now();
  const auto img = radiosity::render(geometry, radiosity::radiance_query(ctx, trainer.network()), settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  image::write_exr(
      out / "cornell-box.exr", img,
      exr_metadata(digest, settings.spp, settings.seed, seconds, static_cast<long long>(trainer.steps_done())));
  image::write_png(out / "cornell-box.png", img);

  if (!fs::exists(ref_path)) {
    reference::RenderOptions ref;
    ref.spp = 1024;
    ref.max_depth = reference::kWholeTransport;
    ref.progress = true;
    reference::RenderStats stats;
    const auto traced = reference::render(geometry, ref, &stats);
    auto attributes = exr_metadata(digest, ref.spp, ref.seed, stats.seconds);
    attributes["pixelFilter"] = filter;
    image::write_exr(ref_path, traced, attributes);
  }
  const auto ref = image::read_exr(ref_path);
  const auto m = image::compare(img, ref);
  std::printf("trained %llu steps; images: %s, %s\nreference (path traced): %s\n%s\n",
              static_cast<unsigned long long>(trainer.steps_done()), (out / "cornell-box.exr").c_str(),
              (out / "cornell-box.png").c_str(), ref_path.c_str(), image::describe(m).c_str());
  return 0;
}

}  // namespace clr::cli
