#pragma once
// A walkthrough's frames (`render --path`, `--orbit`): every camera of a path rendered from one trained model into
// FRAMES_DIR as frame_00000.exr … (and .png), back to back (radiosity::render_frames). Each frame is written
// atomically the moment it completes, so Ctrl-C keeps every finished frame and a rerun renders only the missing
// ones; FRAMES_DIR/frames.json records what the frames are of (scene, model, path, size, spp, seed) and a rerun that
// would mix other frames in is refused.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "geometry/geometry.hpp"
#include "radiosity/renderer.hpp"
#include "scene/camera.hpp"

namespace clr::walkthrough {

struct SequenceOptions {
  std::filesystem::path dir;  // FRAMES_DIR
  bool png = false;           // a tonemapped PNG beside each EXR
  radiosity::RenderSettings settings;
  nlohmann::json record;  // what defines the frames (frames.json), beyond the cameras and settings
  std::map<std::string, std::string> exr_attributes;  // every frame's EXR header records these, and its index
};

struct SequenceResult {
  std::size_t rendered = 0, reused = 0;
  double seconds = 0;  // wall time of the frames rendered now
  bool complete = false;
};

std::filesystem::path frame_path(const std::filesystem::path& dir, std::size_t frame, const char* extension);

// A digest of the cameras (their transforms, fields of view and film): what a rerun's frames must be of.
std::string cameras_digest(const std::vector<scene::Camera>& cameras);

SequenceResult render_sequence(const geometry::Geometry& geometry, const std::vector<scene::Camera>& cameras,
                               const radiosity::RadianceQuery& field, const SequenceOptions& options);

}  // namespace clr::walkthrough
