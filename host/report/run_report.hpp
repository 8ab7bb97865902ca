#pragma once
// A run folder (`train -o RUN_DIR`) as a report: its record and log read, the images it is judged by gathered —
// given as files, else rendered with the engine's own renderers (the model as `render` renders it, at the
// reference's size; the path tracer as `reference` renders it, for the run's training seconds) — and compared with
// the reference as `compare` compares them.
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "report/report_page.hpp"

namespace clr::report {

struct RunReportOptions {
  std::filesystem::path run;
  // The image the others are measured against. Empty: the scene folder's TungstenRender.exr where the run's
  // evaluation.json records its pixels (or the run has no such record), else an InputError asking for it.
  std::filesystem::path reference;
  std::filesystem::path scene;  // empty: the scene file scene.json records
  int sensor = 0;
  // Images given instead of rendered (each the reference's size); empty: rendered.
  std::filesystem::path model_image, path_tracer_image;
  int spp = 0;                     // the model's camera rays a pixel; 0: evaluation.json's, else render's 4
  bool path_tracer = true;         // render the path tracer where no image is given
  double path_tracer_seconds = 0;  // its time budget; 0: the run's training seconds
  int path_tracer_max_spp = 1024;  // and a cap on its samples, so that a long run's report stays cheap
  std::string device;              // --device for the model's render
  // ISNR runs: the I-Module's mixture beside its target (radiosity::view_guide, what `guide` shows) at a grid of
  // guide_grid × guide_grid pixels, precomputed so that the page needs no engine; 0: none.
  int guide_grid = 6;
  int guide_resolution = 32;  // rows of each lat-long map (twice as many columns)
};

// InputError "<option> PATH: …" unless `page` ends in .html (or .htm) and can be written (common/atomic_file.hpp's
// require_output_path), checked before any work.
void require_report_path(const std::filesystem::path& page, const std::string& option);

// Everything the page shows of the run. InputError naming the culprit, before any rendering, for a missing run
// folder, an unreadable config.json or log.csv, a reference that cannot be found or read, and an image of another
// size than the reference.
ReportData run_report(const RunReportOptions& options);

}  // namespace clr::report
