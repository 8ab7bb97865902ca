#pragma once
// The report page (`clradiosity report`, docs/cli.md): one HTML file that opens offline from disk. The page's
// template, script and style are the files under report/, embedded into the binary at build time; the run's data
// (its images as HDR half floats, log.csv's columns, its record) is one JSON object inside the page, which the
// script draws — canvases for the images, inline SVG for the convergence.
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "image/image.hpp"
#include "report/log_table.hpp"

namespace clr::report {

struct ReportImage {
  std::string key;    // "model", "reference", "path_tracer": what the page's script and its tests name it by
  std::string title;  // shown above the image
  image::Image image;
  std::map<std::string, std::string> notes;  // how it was made (spp, seconds, file), shown under it
  std::optional<image::Metrics> metrics;     // against the reference (none for the reference itself)
};

// The path tracer's error at a training time, for the convergence plot (a point beside the model's curve).
struct PathTracerPoint {
  double seconds = 0;
  int spp = 0;
  image::Metrics metrics;
};

struct ReportData {
  std::string title;
  std::vector<ReportImage> images;  // the reference among them, all of one size
  LogTable log;
  std::vector<PathTracerPoint> path_tracer;
  nlohmann::json record = nlohmann::json::object();  // config, scene, device, software: shown as given
  // A sweep's rows (sweep_report.hpp), drawn as time–error curves with their Pareto front; null for a run.
  nlohmann::json sweep = nullptr;
  // The paper tables' scenes (paper_tables_report.hpp): each run's evaluations and the path tracer's points.
  nlohmann::json paper = nullptr;
  // The guide at a grid of pixels (run_report.hpp): per pixel the mixture q and its target as lat-long maps.
  struct GuideView {
    int x = 0, y = 0;        // the pixel, in the images' size
    double kl = 0;           // KL(p‖q)
    image::Image q, target;  // densities per steradian in the red channel (radiosity::GuideView)
  };
  std::vector<GuideView> guide;
};

// The whole page. Throws std::invalid_argument when the images differ in size (a caller's fault: the report checks
// its inputs first).
std::string report_html(const ReportData& data);

// The files under report/ that the page is made of (and bench/paper/paper.json, the paper's numbers), by file name,
// as embedded.
std::string report_asset(const std::string& name);

}  // namespace clr::report
