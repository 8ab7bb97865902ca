#pragma once
// Convergence in one run (`train --reference REF.exr`, docs/cli.md): every S steps, outside the timed training, the
// model is rendered with the scene's camera at the reference's size and its MAPE / MSE / relMSE against the
// reference go into that step's log.csv row; at the end of the run a figure of those columns against steps and
// against training seconds is written beside log.csv. The render is the one `render` makes at the same size and
// spp with its default seed, so a logged figure is exactly `compare` of a `render` of that step's checkpoint.
// The sweep measures its snapshots with the same evaluate_model.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "radiosity/renderer.hpp"

namespace clr::radiosity {

// How a run is evaluated. `spp` and the reference define what the columns mean (recorded in RUN_DIR/
// evaluation.json: a resumed run that measured them another way is refused); `every` is only their cadence.
struct EvaluationSettings {
  std::filesystem::path reference;
  long every = 0;                     // steps between evaluations (the run's last step is evaluated too)
  int spp = RenderSettings{}.spp;     // camera rays per pixel, as `render --spp`
  RenderMode mode = RenderMode::lhs;  // the image, as `render --mode`
  int sensor = 0;                     // the scene's sensor the images are taken from (train --sensor)
};

// The reference an evaluation compares against: InputError naming `file` when it cannot be read, when its aspect
// ratio is not the camera's film's (the model is rendered at the reference's size with the scene's camera: another
// aspect would be another view), or when its header records another scene or sensor (scene/reference_record.hpp;
// one recording less than the whole transport gets a warning line).
image::Image read_evaluation_reference(const std::filesystem::path& file, const scene::Scene& scene, int sensor);

// What RUN_DIR/evaluation.json records of an evaluation: the reference's content (a digest), its size, the spp, the
// image mode and the sensor (the last two recorded only where they are not the defaults, lhs and 0, so that older
// runs' records still match).
nlohmann::json evaluation_record(const EvaluationSettings& settings, const image::Image& reference);

struct Evaluation {
  image::Image image;
  image::Metrics metrics;
  double render_seconds = 0;  // the render alone, not the comparison
};
// Renders `field` with the scene's camera at the reference's size, `spp` rays a pixel in `mode` and `render`'s
// default seed, and compares it with the reference (image::compare).
Evaluation evaluate_model(const geometry::Geometry& geometry, const RadianceQuery& field, const image::Image& reference,
                          int spp, RenderMode mode = RenderMode::lhs);

// The size of a preview of the model: the film scaled down (never up) so that its longer side has at most
// kPreviewSide pixels.
inline constexpr int kPreviewSide = 256;
RenderSettings preview_settings(const scene::Camera& camera);

// RUN_DIR/convergence.svg from log.csv's evaluated rows: MAPE and relMSE against steps and against training
// seconds. Returns the file written, or nullopt (writing nothing) when no row of log.csv has an evaluation.
std::optional<std::filesystem::path> write_convergence_figure(const std::filesystem::path& run_dir);

}  // namespace clr::radiosity
