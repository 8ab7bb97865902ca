#include "report/run_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <optional>

#include "cl/context.hpp"
#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/convergence.hpp"
#include "radiosity/guide/guide_view.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "reference/path_tracer.hpp"
#include "scene/fingerprint.hpp"

namespace clr::report {
namespace fs = std::filesystem;
namespace {

std::string pixels_digest(const image::Image& img) {
  // As evaluation.json records it (radiosity::evaluation_record): the pixels, not the file's bytes.
  return Digest()
      .add(std::string_view(reinterpret_cast<const char*>(img.rgb.data()), img.rgb.size() * sizeof(float)))
      .hex();
}

std::string fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

// An image file given for the report: read, and of the reference's size, else InputError naming the option.
image::Image read_given(const fs::path& file, const std::string& option, const image::Image& reference,
                        std::map<std::string, std::string>& notes) {
  std::map<std::string, std::string> attributes;
  auto img = image::read_exr(file, &attributes);
  if (img.width != reference.width || img.height != reference.height)
    throw InputError(option + " " + file.string() + ": " + std::to_string(img.width) + "x" +
                     std::to_string(img.height) + ", but the reference is " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height));
  notes["file"] = file.string();
  for (const char* key : {"spp", "renderTimeSeconds", "steps", "software"})
    if (attributes.contains(key)) notes[key] = attributes[key];
  return img;
}

// The path tracer for about `seconds`, progressively: one timed sample a pixel, then passes that double the
// samples while the time left allows, and a last pass that fills the rest of it at the measured rate (at most
// `max_spp` samples in all). Each pass draws what a longer render draws (first_sample), so every image along the way
// is the reference path tracer's of that many samples, and each is measured against `reference`: the path
// tracer's error against time for the convergence plot.
image::Image path_trace_for(const geometry::Geometry& geometry, const image::Image& reference, double seconds,
                            int max_spp, std::uint64_t seed, std::vector<PathTracerPoint>& points) {
  reference::RenderOptions options;
  options.seed = seed;
  options.width = reference.width;
  options.height = reference.height;
  options.max_depth = reference::kWholeTransport;
  std::vector<double> sum(reference.rgb.size(), 0.0);
  image::Image img(reference.width, reference.height);
  int spp = 0;
  double spent = 0;
  while (spp < max_spp) {
    int n = std::max(1, spp);  // doubling
    if (spp > 0) {
      const double rate = std::max(spent / spp, 1e-9);
      if (spent + n * rate > seconds) n = int(std::floor((seconds - spent) / rate));  // the rest of the time
      if (n < 1) break;
    }
    n = std::min(n, max_spp - spp);
    options.first_sample = spp;
    options.spp = n;
    reference::RenderStats stats;
    const auto pass = reference::render(geometry, options, &stats);
    spp += n;
    spent += stats.seconds;
    for (std::size_t i = 0; i < sum.size(); ++i) {
      sum[i] += double(pass.rgb[i]) * n;
      img.rgb[i] = float(sum[i] / spp);
    }
    points.push_back({spent, spp, image::compare(img, reference)});
  }
  return img;
}

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

}  // namespace

void require_report_path(const fs::path& page, const std::string& option) {
  if (page.extension() != ".html" && page.extension() != ".htm")
    throw InputError(option + " " + page.string() + ": the report must end in .html");
  require_output_path(page, option);
}

ReportData run_report(const RunReportOptions& opt) {
  using radiosity::RunDirectory;
  // The Python module passes these unchecked by a CLI validator.
  if (opt.guide_grid < 0 || opt.guide_grid > 64)
    throw InputError("guide grid " + std::to_string(opt.guide_grid) + " is not in [0, 64]");
  if (opt.guide_resolution < 8 || opt.guide_resolution > 2048)
    throw InputError("guide resolution " + std::to_string(opt.guide_resolution) + " is not in [8, 2048]");
  if (opt.spp < 0 || opt.spp > (1 << 16)) throw InputError("spp " + std::to_string(opt.spp) + " is not in [1, 65536]");
  if (opt.path_tracer_max_spp < 1 || opt.path_tracer_max_spp > (1 << 20))
    throw InputError("path tracer max spp " + std::to_string(opt.path_tracer_max_spp) + " is not in [1, 2^20]");
  if (!std::isfinite(opt.path_tracer_seconds) || opt.path_tracer_seconds < 0)
    throw InputError("path tracer seconds " + std::to_string(opt.path_tracer_seconds) + " is not finite and >= 0");
  if (!fs::is_directory(opt.run))
    throw InputError(opt.run.string() + (fs::exists(opt.run) ? ": not a folder" : ": no such run folder"));
  ReportData data;
  const fs::path name = opt.run.filename().empty() ? opt.run.parent_path().filename() : opt.run.filename();
  data.title = "clradiosity report: " + name.string();

  // The record first: a run folder without its files is refused before any image is read or made.
  const nlohmann::json config = read_json_file(RunDirectory::config_path(opt.run), "run config");
  const auto train_config = RunDirectory::load_config(opt.run);
  data.log = read_log_table(RunDirectory::log_path(opt.run));
  std::optional<nlohmann::json> scene_record, evaluation;
  if (fs::exists(RunDirectory::scene_path(opt.run)))
    scene_record = read_json_file(RunDirectory::scene_path(opt.run), "run scene record");
  if (fs::exists(RunDirectory::evaluation_path(opt.run)))
    evaluation = read_json_file(RunDirectory::evaluation_path(opt.run), "run evaluation record");
  double trained_seconds = 0;
  long steps = 0;
  if (const auto c = data.log.column("seconds"); c && data.log.rows() > 0) trained_seconds = data.log.values[*c].back();
  if (const auto c = data.log.column("step"); c && data.log.rows() > 0) steps = long(data.log.values[*c].back());

  // The scene: the one given, else the one scene.json records (as it was given to train, relative to where it ran).
  fs::path scene_file = opt.scene;
  std::map<std::string, std::string> parameters;
  if (scene_record) {
    if (scene_file.empty() && scene_record->contains("scene") && (*scene_record)["scene"].is_string())
      scene_file = (*scene_record)["scene"].get<std::string>();
    if (scene_record->contains("parameters") && (*scene_record)["parameters"].is_object())
      for (const auto& [k, v] : (*scene_record)["parameters"].items())
        if (v.is_string()) parameters[k] = v.get<std::string>();
  }

  if (opt.scene.empty() && !scene_file.empty() && !fs::exists(scene_file))
    throw InputError(opt.run.string() + ": its scene " + scene_file.string() +
                     " (as scene.json records it) is not found from here: give --scene SCENE.xml");

  // The reference: given, else what the run recorded measuring against.
  fs::path reference_file = opt.reference;
  if (reference_file.empty()) {
    const fs::path candidate = scene_file.empty() ? fs::path() : scene_file.parent_path() / "TungstenRender.exr";
    bool found = !candidate.empty() && fs::is_regular_file(candidate);
    if (found && evaluation && evaluation->contains("reference"))
      found = pixels_digest(image::read_exr(candidate)) == (*evaluation)["reference"];
    if (!found)
      throw InputError(opt.run.string() +
                       ": no reference recorded for this run (none beside its scene matches evaluation.json): give "
                       "--reference REF.exr");
    reference_file = candidate;
  }
  std::map<std::string, std::string> reference_attributes;
  auto reference = image::read_exr(reference_file, &reference_attributes);
  image::require_usable_reference(reference, "--reference " + reference_file.string());

  ReportImage model{
      "model",
      "model (" + std::string(radiosity::to_string(train_config.method)) + ", step " + std::to_string(steps) + ")",
      {},
      {},
      std::nullopt};
  ReportImage path_tracer{"path_tracer", "path tracer", {}, {}, std::nullopt};
  if (!opt.model_image.empty()) model.image = read_given(opt.model_image, "--model-image", reference, model.notes);
  if (!opt.path_tracer_image.empty())
    path_tracer.image = read_given(opt.path_tracer_image, "--path-tracer-image", reference, path_tracer.notes);
  const bool render_model = opt.model_image.empty();
  const bool guide_grid = opt.guide_grid > 0 && train_config.method == radiosity::Method::Isnr;
  const bool render_path_tracer = opt.path_tracer_image.empty() && opt.path_tracer;

  nlohmann::json record;
  record["run"] = opt.run.string();
  record["steps"] = steps;
  record["training seconds"] = trained_seconds;
  record["reference"] = reference_file.string();
  if (reference_attributes.contains("spp")) record["reference spp"] = reference_attributes["spp"];
  if (render_model || render_path_tracer || guide_grid) {
    if (scene_file.empty())
      throw InputError(opt.run.string() + ": the run records no scene (scene.json) to render it with: give --scene");
    const auto scene = scene::load_scene(scene_file, parameters, opt.sensor);
    RunDirectory::require_scene(opt.run, scene::fingerprint(scene));
    const geometry::Geometry geometry(scene);
    // The model at the reference's size, as `train --reference` evaluates it (its spp and image mode where recorded).
    std::optional<cl::Context> ctx;
    std::unique_ptr<nn::Network> network;
    if (render_model || guide_grid) {
      const auto device = cl::select_device(opt.device);
      ctx.emplace(device);
      network = RunDirectory::load_radiance(*ctx, opt.run);
      record["device"] = device.name;
    }
    if (render_model) {
      int spp = opt.spp;
      if (spp == 0 && evaluation && evaluation->contains("spp")) spp = (*evaluation)["spp"].get<int>();
      if (spp == 0) spp = radiosity::RenderSettings{}.spp;
      const auto mode = evaluation && evaluation->value("mode", "lhs") == "rhs" ? radiosity::RenderMode::rhs
                                                                                : radiosity::RenderMode::lhs;
      const auto e =
          radiosity::evaluate_model(geometry, radiosity::radiance_query(*ctx, *network), reference, spp, mode);
      model.image = e.image;
      model.notes = {{"spp", std::to_string(spp)}, {"render seconds", fixed(e.render_seconds, 3)}};
    }
    // The guide at a grid of pixel centres, as `guide --pixel` computes it; a pixel whose ray meets no surface the
    // model learns is left out.
    if (guide_grid) {
      auto guide = RunDirectory::load_guide(*ctx, opt.run);
      for (int gy = 0; gy < opt.guide_grid; ++gy)
        for (int gx = 0; gx < opt.guide_grid; ++gx) {
          const int x = (2 * gx + 1) * reference.width / (2 * opt.guide_grid);
          const int y = (2 * gy + 1) * reference.height / (2 * opt.guide_grid);
          try {
            auto v = radiosity::view_guide(*ctx, geometry, *network, *guide, float(x) + 0.5f, float(y) + 0.5f,
                                           reference.width, reference.height, opt.guide_resolution);
            data.guide.push_back({x, y, v.kl, std::move(v.q), std::move(v.target)});
          } catch (const InputError&) {
          }
        }
    }
    if (render_path_tracer) {
      const double budget = opt.path_tracer_seconds > 0 ? opt.path_tracer_seconds : trained_seconds;
      // Another seed than the reference's: the path tracer drawing the reference's own samples would match it
      // exactly and measure nothing.
      std::uint64_t seed = 1;
      try {
        if (reference_attributes.contains("seed")) seed = std::stoull(reference_attributes["seed"]) + 1;
      } catch (const std::exception&) {
      }
      path_tracer.image = path_trace_for(geometry, reference, budget, opt.path_tracer_max_spp, seed, data.path_tracer);
      const int spp = data.path_tracer.back().spp;
      const double spent = data.path_tracer.back().seconds;
      path_tracer.title = "path tracer, " + std::to_string(spp) + " spp";
      path_tracer.notes = {{"spp", std::to_string(spp)},
                           {"seconds", fixed(spent, 2)},
                           {"budget seconds", fixed(budget, 2)},
                           {"spp cap", std::to_string(opt.path_tracer_max_spp)},
                           {"seed", std::to_string(seed)}};
    }
  }

  model.metrics = image::compare(model.image, reference);
  data.images.push_back(std::move(model));
  data.images.push_back({"reference", "reference", reference, {{"file", reference_file.string()}}, std::nullopt});
  if (!path_tracer.image.rgb.empty()) {
    path_tracer.metrics = image::compare(path_tracer.image, reference);
    // A given image is one point on the convergence plot: the path tracer's error at the seconds it records.
    if (data.path_tracer.empty()) {
      // The header's numbers where it has readable ones (an image made elsewhere may carry anything there).
      const auto number = [&](const char* key, double otherwise) {
        const auto it = path_tracer.notes.find(key);
        if (it == path_tracer.notes.end()) return otherwise;
        char* end = nullptr;
        const double v = std::strtod(it->second.c_str(), &end);
        return end != it->second.c_str() && std::isfinite(v) ? v : otherwise;
      };
      PathTracerPoint point;
      point.seconds = number("renderTimeSeconds", trained_seconds);
      point.spp = int(number("spp", 0));
      point.metrics = *path_tracer.metrics;
      data.path_tracer.push_back(point);
    }
    data.images.push_back(std::move(path_tracer));
  }

  record["config"] = config;
  if (scene_record) {
    if (scene_record->contains("digest")) record["scene digest"] = (*scene_record)["digest"];
    record["scene"] = *scene_record;
  }
  if (evaluation) record["evaluation"] = *evaluation;
  record["report made by"] = std::string("clradiosity ") + CLR_VERSION;
  record["report made at"] = now_utc();
  data.record = std::move(record);
  return data;
}

}  // namespace clr::report
