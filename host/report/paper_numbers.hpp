#pragma once
// The ISNR paper's own numbers (bench/paper/paper.json, embedded at build time beside the page's files), matched to
// one run of a paper-tables folder, so that the page shows them beside ours without the source tree at hand.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace clr::report {

// Which of the paper's runs a paper-tables run repeats: its table (1: N = 4, 2: N = 32), method (nr, isnr) and the
// I-Module's loss (kl, ikl; empty for nr).
struct PaperRun {
  int table = 0;
  std::string method, loss;
};

// A run's identity from its run.json (bench/paper_tables.sh writes table, method, is_loss), else from its folder
// name as paper_tables.sh names it (t1-nr, t1-isnr-kl, t2-isnr-ikl, …); nullopt when neither says.
std::optional<PaperRun> paper_run(const std::string& label, const nlohmann::json& run_json);

// The embedded paper.json.
const nlohmann::json& paper_numbers();

// The paper's points for `run` on the paper's scene `paper_scene` (its name in the paper, as scene.json's
// paper_scene records it): Tables 1 and 2's final row ({"source", "step", "minutes", "memory_gb", "mape", "mse"};
// the tables show NR and ISNR with IKL only) and, on Table 4's scene, the ablation's points at its steps. Empty for
// a scene the paper does not show.
nlohmann::json paper_points(const nlohmann::json& paper, const std::string& paper_scene, const PaperRun& run);

}  // namespace clr::report
