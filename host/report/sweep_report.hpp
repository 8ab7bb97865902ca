#pragma once
// A sweep folder (`clradiosity sweep -o SWEEP_DIR`) as a report: every configuration's time–error curve from
// results.csv beside the path tracer's, the Pareto front over all of them, the rows as a table with the images the
// sweep kept, and its record (sweep.json, tables.md). Nothing is rendered: the sweep measured everything.
#include <filesystem>

#include "report/report_page.hpp"

namespace clr::report {

// Whether `dir` holds a sweep (its results.csv or sweep.json).
bool is_sweep_folder(const std::filesystem::path& dir);

// InputError naming the file for a sweep without its record or with a damaged results.csv (sweep/results_csv.hpp).
ReportData sweep_report(const std::filesystem::path& dir);

}  // namespace clr::report
