#include "report/sweep_report.hpp"

#include <cmath>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "report/half_image.hpp"
#include "sweep/results_csv.hpp"

namespace clr::report {
namespace fs = std::filesystem;
namespace {

// A PNG the sweep kept, as a data: URL the page shows without a file beside it; null when absent or large (a
// sweep's images are small renders; a large one would only bloat the page).
nlohmann::json embedded_png(const fs::path& dir, const std::string& name) {
  constexpr std::uintmax_t kMaxBytes = 4u << 20;
  if (name.empty()) return nullptr;
  const fs::path file = dir / name;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > kMaxBytes) return nullptr;
  return "data:image/png;base64," + base64(read_input_text(file, "sweep image"));
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

bool is_sweep_folder(const fs::path& dir) {
  return fs::is_regular_file(dir / "results.csv") || fs::is_regular_file(dir / "sweep.json");
}

ReportData sweep_report(const fs::path& dir) {
  const fs::path results = dir / "results.csv";
  if (!fs::is_regular_file(results)) throw InputError(results.string() + ": the sweep has no results yet");
  const auto rows = sweep::read_results(results);
  ReportData data;
  const fs::path name = dir.filename().empty() ? dir.parent_path().filename() : dir.filename();
  data.title = "clradiosity sweep report: " + name.string();
  nlohmann::json out = nlohmann::json::array();
  for (const auto& r : rows) {
    const bool model = r.kind == sweep::RowKind::Model;
    out.push_back(
        {{"kind", sweep::to_string(r.kind)},
         {"point", sweep::to_string(r.point)},
         {"method", r.method},
         {"samples", r.samples},
         {"seed", r.seed},
         {"configuration", model ? r.method + " N=" + std::to_string(r.samples) + " seed " + std::to_string(r.seed)
                                 : std::string("path tracer")},
         {"budget_minutes", number(r.budget_minutes)},
         {"steps", r.steps},
         {"seconds", number(r.seconds)},
         {"spp", r.spp},
         {"peak_device_mib", number(r.peak_device_mib)},
         {"mape", number(r.mape)},
         {"mse", number(r.mse)},
         {"relmse", number(r.relmse)},
         {"incident_samples", r.incident_samples},
         {"image", embedded_png(dir, r.image)},
         {"error_map", embedded_png(dir, r.error_map)}});
  }
  data.sweep = {{"rows", out}};
  if (fs::exists(dir / "sweep.json")) data.record["sweep"] = read_json_file(dir / "sweep.json", "sweep record");
  if (fs::is_regular_file(dir / "tables.md")) data.record["tables.md"] = read_input_text(dir / "tables.md", "tables");
  data.record["sweep folder"] = dir.string();
  return data;
}

}  // namespace clr::report
