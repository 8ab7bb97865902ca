#pragma once
// Rendering from a radiance field (docs/design.md §2): camera ray → delta bounces followed → at the first modelled
// surface x, Le(x) + L(x, −d) (the left-hand side of the rendering equation, the default), or Le(x) plus one sample
// of its right-hand side (`Mode::rhs`, the Neural Radiosity authors' "RHS" image): the direct light by training's
// next-event estimation and one BSDF-sampled direction to the next modelled surface y, where Le + L(y, −ω) closes
// it. The right-hand side carries the BSDF's and the textures' detail exactly and the model's error only through an
// integral; it costs a light sample and a second trace a camera sample, and its Monte Carlo noise. `spp` camera
// rays per pixel, drawn from the film's reconstruction filter as the path tracer draws them (scene/pixel_filter.hpp).
#include <functional>
#include <map>
#include <span>
#include <string>

#include "image/image.hpp"
#include "radiosity/surface_query.hpp"
#include "scene/camera.hpp"

namespace clr::radiosity {

// Scattered radiance for `rows` raw input rows (nn/encoder.hpp layout) → rows × 3 RGB.
using RadianceQuery = std::function<void(std::span<const float> raw_rows, std::span<float> rgb)>;

enum class RenderMode { lhs, rhs };
// The modes by name, for every front end: `render --mode`, `train --eval-mode`, Python's mode= and eval_mode=.
inline const std::map<std::string, RenderMode>& render_mode_names() {
  static const std::map<std::string, RenderMode> names = {{"lhs", RenderMode::lhs}, {"rhs", RenderMode::rhs}};
  return names;
}

struct RenderSettings {
  int width = 0, height = 0;  // 0: the scene's film
  int spp = 4;
  RenderMode mode = RenderMode::lhs;
  std::uint64_t seed = 1;
  int max_delta_bounces = 8;
  std::size_t rows_per_query = 1 << 16;  // lookups per call of the field: bounds host and device memory
};

image::Image render(const geometry::Geometry& geometry, const RadianceQuery& field, const RenderSettings& settings);

// Frames of several cameras (a camera path) rendered back to back: the chunks of camera samples that go to the
// field span frames, so that frames too small to fill the device alone do not leave it idle between them. Each
// frame is the image `render` gives with its camera (the same sample streams). `done(i, image)` receives frame i,
// in order, as soon as its last sample is in; `stop()` is asked between chunks — the frames done stay done.
void render_frames(const geometry::Geometry& geometry, std::span<const scene::Camera> cameras,
                   const RadianceQuery& field, const RenderSettings& settings,
                   const std::function<void(std::size_t frame, image::Image&& image)>& done,
                   const std::function<bool()>& stop = {});

}  // namespace clr::radiosity
