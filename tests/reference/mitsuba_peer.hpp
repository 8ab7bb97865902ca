#pragma once
// Mitsuba 3 as the peer renderer of the slow tests (tests/reference/mitsuba_render.py, scalar_rgb): its seeded
// renders, and both sides of the multi-seed judgement (peer_judgement.hpp) that the corpus peer and the shared and
// bundled scenes' peer test share.
#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "reference/path_tracer.hpp"
#include "reference/peer_judgement.hpp"

namespace clr::test {

inline bool have_mitsuba() { return std::system("python3 -c 'import mitsuba' >/dev/null 2>&1") == 0; }

// Mitsuba's renders of `xml` at width × height with spp samples and max_depth, seeded first_seed … first_seed +
// count − 1 (the scene loaded once); nullopt where Mitsuba cannot load the scene (the script exits 3). Throws on any
// other failure.
inline std::optional<std::vector<image::Image>> mitsuba_renders(const std::filesystem::path& xml, int width, int height,
                                                                int spp, int max_depth, int first_seed, int count) {
  const auto out = std::filesystem::temp_directory_path() / ("clr_mitsuba_" + std::to_string(::getpid()) + ".exr");
  const std::string cmd = "python3 '" CLR_SOURCE_DIR "/tests/reference/mitsuba_render.py' '" + xml.string() + "' " +
                          std::to_string(width) + " " + std::to_string(height) + " " + std::to_string(spp) + " " +
                          std::to_string(max_depth) + " '" + out.string() + "' " + std::to_string(first_seed) + " " +
                          std::to_string(count) + " 2>/dev/null";
  const int status = std::system(cmd.c_str());
  if (WIFEXITED(status) && WEXITSTATUS(status) == 3) return std::nullopt;
  if (status != 0) throw std::runtime_error("failed: " + cmd);
  std::vector<image::Image> images;
  for (int seed = first_seed; seed < first_seed + count; ++seed) {
    const auto file = std::filesystem::path(out).replace_extension().string() + "-" + std::to_string(seed) + ".exr";
    images.push_back(image::read_exr(file));
    std::filesystem::remove(file);
  }
  return images;
}

// The two sides of a peer judgement (peer_judgement.hpp) at width × height: our path tracer's seeded renders of
// `geometry`, and Mitsuba's of `xml` (which the caller has seen Mitsuba load) at the scene's max_depth.
inline SeededRender our_seeds(const geometry::Geometry& geometry, int width, int height) {
  return [&geometry, width, height](int spp, int first_seed, int seeds) {
    std::vector<image::Image> images;
    reference::RenderOptions opt;
    opt.width = width;
    opt.height = height;
    opt.spp = spp;
    for (int s = first_seed; s < first_seed + seeds; ++s) {
      opt.seed = std::uint64_t(s);
      images.push_back(reference::render(geometry, opt));
    }
    return images;
  };
}
inline SeededRender mitsuba_seeds(const std::filesystem::path& xml, int width, int height, int max_depth) {
  return [xml, width, height, max_depth](int spp, int first_seed, int seeds) {
    auto images = mitsuba_renders(xml, width, height, spp, max_depth, first_seed, seeds);
    if (!images) throw std::runtime_error("Mitsuba 3 cannot load " + xml.string());
    return std::move(*images);
  };
}

}  // namespace clr::test
