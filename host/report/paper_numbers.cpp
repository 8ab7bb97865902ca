#include "report/paper_numbers.hpp"

#include <regex>

#include "report/report_page.hpp"

namespace clr::report {

std::optional<PaperRun> paper_run(const std::string& label, const nlohmann::json& run_json) {
  PaperRun run;
  if (run_json.is_object() && run_json.contains("table") && run_json["table"].is_number_integer() &&
      run_json.contains("method") && run_json["method"].is_string()) {
    run.table = run_json["table"].get<int>();
    run.method = run_json["method"].get<std::string>();
    if (run.method != "nr" && run_json.contains("is_loss") && run_json["is_loss"].is_string())
      run.loss = run_json["is_loss"].get<std::string>();
    return run;
  }
  static const std::regex name("t([12])-(nr|isnr)(?:-(kl|ikl))?");
  std::smatch m;
  if (!std::regex_match(label, m, name)) return std::nullopt;
  run.table = std::stoi(m[1]);
  run.method = m[2];
  run.loss = m[3];
  if (run.method == "isnr" && run.loss.empty()) run.loss = "ikl";  // the trainer's default
  return run;
}

const nlohmann::json& paper_numbers() {
  static const nlohmann::json paper = nlohmann::json::parse(report_asset("paper.json"));
  return paper;
}

nlohmann::json paper_points(const nlohmann::json& paper, const std::string& paper_scene, const PaperRun& run) {
  nlohmann::json points = nlohmann::json::array();
  if (paper_scene.empty()) return points;
  // Tables 1 and 2 show NR and the full method (ISNR with IKL) alone.
  const std::string key = run.method == "nr" ? "nr" : run.loss == "ikl" ? "isnr" : "";
  const std::string table = "table" + std::to_string(run.table);
  if (!key.empty() && paper.contains(table)) {
    const auto& rows = paper[table]["rows"];
    if (rows.contains(paper_scene) && rows[paper_scene].contains(key)) {
      nlohmann::json p = rows[paper_scene][key];
      p["source"] = "Table " + std::to_string(run.table);
      points.push_back(std::move(p));
    }
  }
  // Table 4's ablation (Table 1's N): w/o I-Module = NR, w/o IKL = ISNR with KL, full = ISNR with IKL.
  const auto& t4 = paper.contains("table4") ? paper["table4"] : nlohmann::json();
  const std::string ablation = run.method == "nr" ? "nr" : run.loss;
  if (run.table == 1 && t4.is_object() && t4.value("scene", "") == paper_scene && t4.contains("steps") &&
      t4.contains("mape") && t4.contains("mse") && t4["mape"].contains(ablation))
    for (std::size_t i = 0; i < t4["steps"].size(); ++i)
      points.push_back({{"source", "Table 4"},
                        {"step", t4["steps"][i]},
                        {"mape", t4["mape"][ablation][i]},
                        {"mse", t4["mse"][ablation][i]}});
  return points;
}

}  // namespace clr::report
