#include "radiosity/convergence.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <sstream>
#include <string_view>

#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "image/line_chart.hpp"
#include "radiosity/run_directory.hpp"
#include "scene/fingerprint.hpp"
#include "scene/reference_record.hpp"

namespace clr::radiosity {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// A field of log.csv as a number; NaN when it is empty (a row without an evaluation) or not a number.
double field_value(const std::vector<std::string>& fields, std::size_t column) {
  if (column >= fields.size() || fields[column].empty()) return NAN;
  char* end = nullptr;
  const double v = std::strtod(fields[column].c_str(), &end);
  return end == fields[column].c_str() ? NAN : v;
}

}  // namespace

image::Image read_evaluation_reference(const fs::path& file, const scene::Scene& scene, int sensor) {
  const scene::Camera& camera = scene.camera;
  image::Image reference;
  std::map<std::string, std::string> attributes;
  try {
    reference = image::read_exr(file, &attributes);
  } catch (const InputError& e) {
    throw InputError("--reference " + file.string() + ": " + e.what());
  }
  image::require_usable_reference(reference, "--reference " + file.string());
  if (const std::string warning = scene::check_reference_record(attributes, scene::fingerprint(scene).digest, sensor,
                                                                "--reference", file.string());
      !warning.empty())
    std::cerr << "train: warning: " << warning << "\n";
  // Equal ratios in integers: a film of 1280×720 takes a reference of 640×360 or 2560×1440, not 640×361.
  if (std::int64_t(reference.width) * camera.height != std::int64_t(reference.height) * camera.width)
    throw InputError("--reference " + file.string() + ": " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height) + " is not the shape of the scene's film (" +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                     "); the model is rendered at the reference's size with the scene's camera");
  return reference;
}

nlohmann::json evaluation_record(const EvaluationSettings& settings, const image::Image& reference) {
  // The pixels, not the file's bytes: the same image saved with another compression is the same reference.
  const std::string_view pixels(reinterpret_cast<const char*>(reference.rgb.data()),
                                reference.rgb.size() * sizeof(float));
  nlohmann::json record = {{"reference", Digest().add(pixels).hex()},
                           {"width", reference.width},
                           {"height", reference.height},
                           {"spp", settings.spp}};
  if (settings.mode == RenderMode::rhs) record["mode"] = "rhs";
  if (settings.sensor != 0) record["sensor"] = settings.sensor;
  return record;
}

Evaluation evaluate_model(const geometry::Geometry& geometry, const RadianceQuery& field, const image::Image& reference,
                          int spp, RenderMode mode) {
  RenderSettings settings;  // `render`'s defaults (its seed among them) but for the size, spp and mode
  settings.width = reference.width;
  settings.height = reference.height;
  settings.spp = spp;
  settings.mode = mode;
  Evaluation e;
  const auto start = std::chrono::steady_clock::now();
  e.image = render(geometry, field, settings);
  e.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  e.metrics = image::compare(e.image, reference);
  return e;
}

RenderSettings preview_settings(const scene::Camera& camera) {
  RenderSettings settings;
  const double scale = std::min(1.0, double(kPreviewSide) / double(std::max(camera.width, camera.height)));
  settings.width = std::max(1, int(std::lround(camera.width * scale)));
  settings.height = std::max(1, int(std::lround(camera.height * scale)));
  return settings;
}

std::optional<fs::path> write_convergence_figure(const fs::path& run_dir) {
  std::istringstream log(read_input_text(RunDirectory::log_path(run_dir), "run log"));
  std::string line;
  if (!std::getline(log, line)) return std::nullopt;
  const auto header = split(line);
  const auto column = [&](const char* name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t step = column("step"), seconds = column("seconds"), mape = column("mape"),
                    relmse = column("relmse");
  if (mape >= header.size()) return std::nullopt;  // a log from before evaluations were logged
  std::vector<double> steps, secs, mapes, relmses;
  while (std::getline(log, line)) {
    const auto fields = split(line);
    const double m = field_value(fields, mape);
    if (!std::isfinite(m)) continue;  // a row without an evaluation
    steps.push_back(field_value(fields, step));
    secs.push_back(field_value(fields, seconds));
    mapes.push_back(m);
    relmses.push_back(field_value(fields, relmse));
  }
  if (mapes.empty()) return std::nullopt;
  const fs::path file = RunDirectory::convergence_path(run_dir);
  const auto panel = [&](const char* title, const char* x_label, const std::vector<double>& x) {
    return image::ChartPanel{title, x_label, "error", true, {{"MAPE", x, mapes}, {"relMSE", x, relmses}}};
  };
  const fs::path name = run_dir.filename().empty() ? run_dir.parent_path().filename() : run_dir.filename();
  write_text_atomically(file, image::line_chart_svg("Convergence of " + name.string(),
                                                    {panel("against steps", "step", steps),
                                                     panel("against training time", "training seconds", secs)}));
  return file;
}

}  // namespace clr::radiosity
