#pragma once
// Mitsuba 3 as the peer renderer of the slow tests (tests/reference/mitsuba_render.py, scalar_rgb), and the
// judgement of the shared and bundled scenes' peer test (mitsuba_peer_slow_test.cpp): our render and Mitsuba's, each
// as two half-sample renders with different seeds, agree within 1 % (channel means) and 2 % (median 8×8-block
// error), widened by the noise of both averages. The corpus peer judges over 10 seeds instead (peer_judgement.hpp).
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image/image.hpp"
#include "reference/agreement.hpp"

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

// One seeded render, as mitsuba_renders.
inline std::optional<image::Image> mitsuba_render(const std::filesystem::path& xml, int width, int height, int spp,
                                                  int max_depth, int seed) {
  auto images = mitsuba_renders(xml, width, height, spp, max_depth, seed, 1);
  if (!images) return std::nullopt;
  return std::move(images->front());
}

// Ours (a, b) against the peer's (p, q): each pair two half-sample renders with different seeds.
struct PeerVerdict {
  Agreement agreement;
  Noise ours, peer;
  double mean_bound = 0, block_bound = 0;
  bool agrees() const { return agreement.worst_mean_error < mean_bound && agreement.median_block_error < block_bound; }
};

inline PeerVerdict judge_against_peer(const image::Image& a, const image::Image& b, const image::Image& p,
                                      const image::Image& q) {
  PeerVerdict v;
  const image::Image peer = average(p, q);
  v.agreement = agreement(average(a, b), peer);
  v.ours = noise_of_average(a, b, peer);
  v.peer = noise_of_average(p, q, peer);
  // The difference of two independent averages carries both noises; 3 (means) and 2 (median block) standard
  // deviations of it on top of the systematic allowance.
  v.mean_bound = 0.01 + 3 * std::hypot(v.ours.mean, v.peer.mean);
  v.block_bound = 0.02 + 2 * std::hypot(v.ours.median_block, v.peer.median_block);
  return v;
}

inline std::ostream& operator<<(std::ostream& os, const PeerVerdict& v) {
  return os << v.agreement << "; noise (ours, Mitsuba's): mean " << 100 * v.ours.mean << " %, " << 100 * v.peer.mean
            << " %, median block " << 100 * v.ours.median_block << " %, " << 100 * v.peer.median_block << " %; bounds "
            << 100 * v.mean_bound << " %, " << 100 * v.block_bound << " %";
}

}  // namespace clr::test
