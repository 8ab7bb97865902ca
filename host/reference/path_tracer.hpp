#pragma once
// The reference: a unidirectional path tracer with next-event estimation, multiple importance sampling (power
// heuristic) and Russian roulette, over the same scene, geometry and BSDF code the trainer uses. Every sample of
// every pixel draws from its own PCG32 stream (Pcg32::for_sample: pixel y·width + x, sample index, seed), so an image
// depends only on the seed, never on the thread count, and the first n samples are the same in a longer render.
// The image is rendered in passes of a few samples per pixel, summed in double, so that a stop keeps whole passes.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "geometry/geometry.hpp"
#include "image/image.hpp"

namespace clr::reference {

// The path length of an image a trained model is measured against: the whole transport, which training solves
// whatever the scene's integrator renders (its `direct`, or a short max_depth, would measure the model against less
// light than it learned).
inline constexpr int kWholeTransport = -1;

struct RenderOptions {
  int width = 0, height = 0;            // 0: the scene's film
  std::optional<scene::Camera> camera;  // another view than the scene's sensor (a frame of a camera path)
  int spp = 16;
  // The samples drawn are [first_sample, first_sample + spp): a render that continues one of first_sample samples
  // (`reference --resume`) draws what a longer render would have.
  int first_sample = 0;
  // Longest path in segments (1: emitters seen directly only); -1: unbounded (roulette ends it). Unset: the
  // scene's integrator max_depth.
  std::optional<int> max_depth;
  std::uint64_t seed = 0;
  bool progress = false;  // print progress on stderr
  // Only rows y ≡ row_offset (mod row_stride) are rendered, the rest left 0: an MPI rank's share of the image.
  // Interleaved rows give every rank a like mix of the image's costly and cheap parts.
  int row_offset = 0, row_stride = 1;
  // A stop (common/stop_signal.hpp) ends the render within moments: the pass under way is dropped and the image is
  // the mean of the passes finished, RenderStats::spp of them (0: an image of zeros that measures nothing).
  bool stoppable = false;
  // Called on the calling thread after each pass (an MPI rank says it is computing, not lost).
  std::function<void()> between_passes;
};

struct RenderStats {
  int spp = 0;  // samples per pixel in the image: RenderOptions::spp unless a stop cut the render short
  double seconds = 0;
  std::uint64_t paths = 0;       // of the rows rendered
  std::uint64_t rays = 0;        // closest-hit and shadow rays
  std::uint64_t non_finite = 0;  // samples of the image's passes dropped (counted as 0) for being NaN or infinite
};

image::Image render(const geometry::Geometry& geometry, const RenderOptions& options, RenderStats* stats = nullptr);

// The samples per pixel a reference of `scene` (read from `path`) takes, as mitsuba renders a scene: `given` where
// it is not 0, else its <sampler>'s sample_count. InputError "<option>: …" where neither gives a count in [1, 2^24].
int samples_per_pixel(const scene::Scene& scene, const std::string& path, int given, const std::string& option);

}  // namespace clr::reference
