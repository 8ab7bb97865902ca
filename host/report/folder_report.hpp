#pragma once
// The report of whatever folder it is given: a sweep's and the paper tables' from what they measured, a run's from
// its files and the renders it needs (`clradiosity report`, `train --report`, the Python module's report()).
#include "report/report_page.hpp"
#include "report/run_report.hpp"

namespace clr::report {

ReportData folder_report(const RunReportOptions& options);

}  // namespace clr::report
