#include "report/folder_report.hpp"

#include "report/paper_tables_report.hpp"
#include "report/sweep_report.hpp"

namespace clr::report {

ReportData folder_report(const RunReportOptions& options) {
  if (is_sweep_folder(options.run)) return sweep_report(options.run);
  if (is_paper_tables_folder(options.run)) return paper_tables_report(options.run);
  return run_report(options);
}

}  // namespace clr::report
