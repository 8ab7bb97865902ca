#include "report/paper_tables_report.hpp"

#include <algorithm>
#include <cmath>

#include "common/input_file.hpp"
#include "report/log_table.hpp"

namespace clr::report {
namespace fs = std::filesystem;
namespace {

std::vector<fs::path> sorted_folders(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The named columns of `table` as JSON arrays (NaN as null); a column the file lacks is left out.
nlohmann::json columns(const LogTable& table, std::initializer_list<const char*> names) {
  nlohmann::json out = nlohmann::json::object();
  for (const char* name : names)
    if (const auto c = table.column(name)) out[name] = table.values[*c];
  return out;
}

}  // namespace

bool is_paper_tables_folder(const fs::path& dir) {
  return fs::is_directory(dir / "runs") && (fs::is_directory(dir / "path_tracer") || fs::exists(dir / "tables.md"));
}

ReportData paper_tables_report(const fs::path& dir) {
  ReportData data;
  const fs::path name = dir.filename().empty() ? dir.parent_path().filename() : dir.filename();
  data.title = "clradiosity paper tables: " + name.string();
  nlohmann::json scenes = nlohmann::json::array();
  for (const auto& scene_dir : sorted_folders(dir / "runs")) {
    nlohmann::json scene = {{"name", scene_dir.filename().string()}, {"runs", nlohmann::json::array()}};
    if (fs::exists(scene_dir / "scene.json"))
      scene["record"] = read_json_file(scene_dir / "scene.json", "scene record");
    for (const auto& run : sorted_folders(scene_dir)) {
      if (!fs::exists(run / "log.csv")) continue;
      const auto log = read_log_table(run / "log.csv");
      scene["runs"].push_back({{"label", run.filename().string()},
                               {"columns", columns(log, {"step", "seconds", "samples", "mape", "mse"})}});
    }
    const fs::path points = dir / "path_tracer" / scene_dir.filename() / "points.csv";
    if (fs::exists(points))
      scene["path_tracer"] =
          columns(read_csv_table(points, "seconds", "path tracer's points"), {"spp", "seconds", "mape", "mse"});
    scenes.push_back(std::move(scene));
  }
  data.paper = {{"scenes", scenes}};
  if (fs::is_regular_file(dir / "tables.md")) data.record["tables.md"] = read_input_text(dir / "tables.md", "tables");
  data.record["paper tables folder"] = dir.string();
  return data;
}

}  // namespace clr::report
