#pragma once
// Where training pays for itself (`render --path … --path-tracer-check K`): a trained model renders every further
// view for the cost of a render, the path tracer pays per frame. K frames of the path, evenly spaced, are rendered
// by the model (timed back to back, as the walkthrough renders them) and path-traced progressively — passes of
// doubling spp, each with its own seed, their spp-weighted mean the image — until each reaches the model's MAPE
// against a high-spp reference of that frame (as a sweep's path-tracer row does). Then training_seconds /
// (path tracer s/frame − model s/frame) is the number of frames after which the model is cheaper.
#include <nlohmann/json.hpp>
#include <vector>

#include "geometry/geometry.hpp"
#include "radiosity/renderer.hpp"
#include "scene/camera.hpp"

namespace clr::walkthrough {

struct BreakEvenOptions {
  int frames_checked = 3;
  int reference_spp = 1024;
  radiosity::RenderSettings settings;  // the model's renders: size, spp, seed
  double training_seconds = 0;         // the run's, from its log
  // The model's seconds per frame as the walkthrough measured them over its whole path (0: not measured in this
  // process — the K frames are then timed back to back).
  double model_seconds_per_frame = 0;
  // A frame's path tracing stops doubling before a pass expected to end past this many seconds; its time at the
  // model's MAPE is then extrapolated with MAPE ∝ time^-1/2 (the Monte Carlo rate) and marked so.
  double cap_seconds = 600;
};

struct FrameCheck {
  std::size_t frame = 0;
  double model_mape = 0, path_tracer_mape = 0;
  double path_tracer_seconds = 0;  // to reach model_mape
  int path_tracer_spp = 0;         // of the last pass chain measured
  bool extrapolated = false;
};

struct BreakEven {
  double model_seconds_per_frame = 0, path_tracer_seconds_per_frame = 0, training_seconds = 0;
  double frames = 0;  // after which the model is cheaper; infinity when the path tracer is as fast per frame
  std::vector<FrameCheck> checks;
  nlohmann::json to_json() const;
};

// A stop (SIGINT, SIGTERM, SIGHUP) ends it within moments, with the frames checked so far; the caller reports
// nothing when stop_requested().
BreakEven measure_break_even(const geometry::Geometry& geometry, const std::vector<scene::Camera>& cameras,
                             const radiosity::RadianceQuery& field, const BreakEvenOptions& options);

}  // namespace clr::walkthrough
