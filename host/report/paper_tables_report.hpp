#pragma once
// A paper-tables folder (bench/paper_tables.sh OUT_DIR) as a report: for each scene, every run's MAPE against
// steps, seconds and samples trained on (their log.csv evaluations) with the path tracer's points beside them, and
// tables.md — our rows beside the paper's numbers, as bench/paper_tables.py wrote them — as the record.
#include <filesystem>

#include "report/report_page.hpp"

namespace clr::report {

// Whether `dir` is what bench/paper_tables.sh writes: a runs/ folder of scenes beside path_tracer/ or tables.md.
bool is_paper_tables_folder(const std::filesystem::path& dir);

// InputError naming the file for a damaged log.csv, points.csv or scene record.
ReportData paper_tables_report(const std::filesystem::path& dir);

}  // namespace clr::report
