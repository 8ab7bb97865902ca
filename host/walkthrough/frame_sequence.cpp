#include "walkthrough/frame_sequence.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/folder_record.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "image/image.hpp"

namespace clr::walkthrough {
namespace fs = std::filesystem;

fs::path frame_path(const fs::path& dir, std::size_t frame, const char* extension) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05zu.%s", frame, extension);
  return dir / name;
}

std::string cameras_digest(const std::vector<scene::Camera>& cameras) {
  Digest d;
  for (const auto& c : cameras) {
    d.add({reinterpret_cast<const char*>(&c.to_world), sizeof c.to_world});
    for (const float v : {c.fov_degrees, c.near_clip, c.far_clip}) d.add({reinterpret_cast<const char*>(&v), sizeof v});
    const int film[] = {c.width, c.height, int(c.fov_axis), int(c.projection)};
    d.add({reinterpret_cast<const char*>(film), sizeof film});
  }
  return d.hex();
}

SequenceResult render_sequence(const geometry::Geometry& geometry, const std::vector<scene::Camera>& cameras,
                               const radiosity::RadianceQuery& field, const SequenceOptions& o) {
  nlohmann::json record = o.record;
  record["frames"] = cameras.size();
  record["cameras"] = cameras_digest(cameras);
  record["width"] = o.settings.width;
  record["height"] = o.settings.height;
  record["spp"] = o.settings.spp;
  record["seed"] = o.settings.seed;
  fs::create_directories(o.dir);
  // Frames the record would describe: any frame file, and beyond the path's length, frames the record cannot hold.
  std::string content;
  for (const auto& e : fs::directory_iterator(o.dir)) {
    const std::string name = e.path().filename().string();
    if (!name.starts_with("frame_")) continue;
    content = "frames (" + name + ")";
    const std::size_t number = std::strtoull(name.c_str() + 6, nullptr, 10);
    if (number >= cameras.size() && fs::exists(o.dir / "frames.json"))
      throw InputError(o.dir.string() + " holds " + name + ", beyond the " + std::to_string(cameras.size()) +
                       " frames its record describes: the folder was made with another path; use another folder");
  }
  require_same_record(o.dir / "frames.json", record, "frames",
                      {{"scene", "the scene (its files)"},
                       {"model", "--model (its checkpoint)"},
                       {"frames", "--path or --orbit (the frame count)"},
                       {"cameras", "--path or --orbit (the cameras)"},
                       {"width", "--width"},
                       {"height", "--height"},
                       {"spp", "--spp"},
                       {"seed", "--seed"}},
                      content);

  // Frames done by an earlier run (their EXR is written atomically, so one that exists is complete).
  SequenceResult result;
  std::vector<std::size_t> missing;
  std::vector<scene::Camera> views;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    if (fs::exists(frame_path(o.dir, i, "exr"))) {
      if (o.png && !fs::exists(frame_path(o.dir, i, "png")))
        image::write_png(frame_path(o.dir, i, "png"), image::read_exr(frame_path(o.dir, i, "exr")));
      ++result.reused;
      continue;
    }
    missing.push_back(i);
    views.push_back(cameras[i]);
  }
  Progress progress("render", double(cameras.size()), 5.0, double(result.reused));
  progress.update(double(result.reused));
  const auto start = std::chrono::steady_clock::now();
  radiosity::render_frames(
      geometry, views, field, o.settings,
      [&](std::size_t k, image::Image&& img) {
        const std::size_t i = missing[k];
        if (o.png) image::write_png(frame_path(o.dir, i, "png"), img);
        auto attributes = o.exr_attributes;
        attributes["frame"] = std::to_string(i);
        image::write_exr(frame_path(o.dir, i, "exr"), img, attributes);  // last: its presence marks the frame done
        ++result.rendered;
        progress.update(double(result.reused + result.rendered), "frame " + std::to_string(i));
      },
      [] { return stop_requested(); });
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.complete = result.reused + result.rendered == cameras.size();
  progress.finish(std::to_string(result.rendered) + " frames rendered, " + std::to_string(result.reused) +
                  " kept from an earlier run");
  return result;
}

}  // namespace clr::walkthrough
