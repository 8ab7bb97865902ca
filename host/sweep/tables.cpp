#include "sweep/tables.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "sweep/path_tracing.hpp"
#include "sweep/sweep_plan.hpp"

namespace clr::sweep {
namespace {

std::string g(double v, const char* format = "%.4g") {
  if (std::isnan(v)) return "—";
  char s[64];
  std::snprintf(s, sizeof s, format, v);
  return s;
}

std::string seconds_text(double s) { return std::isnan(s) ? "—" : s < 120 ? g(s, "%.3g s") : g(s / 60, "%.1f min"); }

// Incident samples seen, in millions; "—" where unknown (0: a row from before the column).
std::string samples_text(double samples) { return samples > 0 ? g(samples / 1e6, "%.4g M") : "—"; }

std::string memory_text(double mib) {
  return std::isnan(mib) ? "—" : mib < 1024 ? g(mib, "%.3g MiB") : g(mib / 1024, "%.2f GiB");
}

// Mean over the seeds of one (N, budget, method): the paper reports single runs; with several seeds the mean is
// what compares, and the seed count says how many runs stand behind it.
struct Mean {
  int runs = 0;
  double steps = 0, incident_samples = 0, seconds = 0, memory = 0, mape = 0, mse = 0, relmse = 0, residual = 0,
         render_seconds = 0;
  int spp = 0;
  void add(const Row& r) {
    ++runs;
    steps += double(r.steps);
    incident_samples += double(r.incident_samples);
    seconds += r.seconds;
    memory += r.peak_device_mib;
    mape += r.mape;
    mse += r.mse;
    relmse += r.relmse;
    residual += r.residual;
    render_seconds += r.render_seconds;
    spp = r.spp;
  }
  double of(double sum) const { return sum / double(runs); }
};

using GroupKey = std::tuple<int, double, std::string>;  // N, budget, method

const Row* find_steps_row(const std::vector<Row>& rows, const Row& like, const std::string& method) {
  for (const auto& r : rows)
    if (r.kind == RowKind::Model && r.point == Point::Steps && r.method == method && r.samples == like.samples &&
        r.seed == like.seed && r.steps == like.steps)
      return &r;
  return nullptr;
}

}  // namespace

std::string tables_markdown(const std::vector<Row>& rows, const std::string& title) {
  std::map<GroupKey, Mean> means;
  std::set<std::string> methods;
  std::set<int> samples;
  for (const auto& r : rows)
    if (r.kind == RowKind::Model && r.point == Point::Budget) {
      means[{r.samples, r.budget_minutes, r.method}].add(r);
      methods.insert(r.method);
      samples.insert(r.samples);
    }
  std::string md = "# " + title + "\n\n";
  md +=
      "Every configuration is one training run; a budget's row is that run's snapshot when its training time reached "
      "the budget (a mid-schedule point: the learning rate anneals over the largest budget). Time is training time "
      "(rendering the snapshots is not counted), memory the peak of the device buffers, metrics against the "
      "reference over all pixels and channels. Means over seeds where there are several.\n\n";

  // The paper's Tables 1 and 2: per N, each ISNR run at a budget beside NR at the same step count.
  md +=
      "## Table 1 — equal steps\n\nEach ISNR row is a run at a budget; the NR row under it is NR's snapshot at the "
      "same step count (same N and seed), taken on the way through its own run.\n\n";
  for (int n : samples) {
    md += "N = " + std::to_string(n) +
          "\n\n| budget | seed | method | steps | samples seen | time | memory | MAPE | MSE | relMSE |\n"
          "| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const auto& r : rows) {
      if (r.kind != RowKind::Model || r.point != Point::Budget || r.samples != n || r.method == "nr") continue;
      const auto line = [&](const Row& x, const std::string& label) {
        return "| " + budget_label(r.budget_minutes) + " | " + std::to_string(r.seed) + " | " + label + " | " +
               std::to_string(x.steps) + " | " + samples_text(double(x.incident_samples)) + " | " +
               seconds_text(x.seconds) + " | " + memory_text(x.peak_device_mib) + " | " + g(x.mape) + " | " + g(x.mse) +
               " | " + g(x.relmse) + " |\n";
      };
      md += line(r, r.method);
      if (const Row* nr = find_steps_row(rows, r, "nr"))
        md += line(*nr, "nr, same steps");
      else
        md +=
            "| | | nr, same steps | — (not reached within NR's largest budget, or NR not in the sweep) | | | | | | |\n";
    }
    md += "\n";
  }

  md +=
      "## Table 2 — equal time\n\nEvery method at each budget of training time, and the path tracer at the same "
      "time of rendering (its spp chosen to fit the budget from the rate measured so far, in passes until "
      "within 5 % of it; the time is measured, and a busy machine can push it past the budget). Samples seen are "
      "the incident samples trained on (steps × batch × N): configurations compare at equal samples by them.\n\n| "
      "N | budget | method | seeds | steps | samples seen | time | memory | MAPE | MSE | relMSE | residual |\n"
      "| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& [key, m] : means) {
    const auto& [n, budget, method] = key;
    md += "| " + std::to_string(n) + " | " + budget_label(budget) + " | " + method + " | " + std::to_string(m.runs) +
          " | " + g(m.of(m.steps), "%.0f") + " | " + samples_text(m.of(m.incident_samples)) + " | " +
          seconds_text(m.of(m.seconds)) + " | " + memory_text(m.of(m.memory)) + " | " + g(m.of(m.mape)) + " | " +
          g(m.of(m.mse)) + " | " + g(m.of(m.relmse)) + " | " + g(m.of(m.residual)) + " |\n";
  }
  for (const auto& r : rows)
    if (r.kind == RowKind::PathTracing && r.point == Point::Budget)
      md += "| | " + budget_label(r.budget_minutes) + " | path tracing, " + std::to_string(r.spp) + " spp | | | | " +
            seconds_text(r.seconds) + " | | " + g(r.mape) + " | " + g(r.mse) + " | " + g(r.relmse) + " | |\n";
  md += "\n";

  md +=
      "## Table 3 — residual at equal time and equal samples\n\nThe rendering-equation residual metric (lower is "
      "closer to the solution): NR and each ISNR variant after the same training time, and NR after the same "
      "number of steps — so the same number of training samples — as the ISNR variant took in that time.\n\n"
      "| N | budget | nr (equal time) | method | its residual (equal time) | nr at its steps (equal samples) |\n"
      "| ---: | ---: | ---: | --- | ---: | ---: |\n";
  for (const auto& [key, m] : means) {
    const auto& [n, budget, method] = key;
    if (method == "nr") continue;
    const auto nr = means.find({n, budget, "nr"});
    Mean same_steps;
    for (const auto& r : rows)
      if (r.kind == RowKind::Model && r.point == Point::Budget && r.method == method && r.samples == n &&
          r.budget_minutes == budget)
        if (const Row* s = find_steps_row(rows, r, "nr")) same_steps.add(*s);
    md += "| " + std::to_string(n) + " | " + budget_label(budget) + " | " +
          (nr == means.end() ? "—" : g(nr->second.of(nr->second.residual))) + " | " + method + " | " +
          g(m.of(m.residual)) + " | " + (same_steps.runs ? g(same_steps.of(same_steps.residual)) : "—") + " |\n";
  }
  md += "\n";

  md +=
      "## Rendering a trained model against path tracing at equal error\n\nThe model's render time (at the "
      "sweep's spp, on the device) beside the time the path tracer (all CPU cores) needs for an image of the same "
      "MAPE: interpolated between its measured points, or — marked ≈ — extrapolated from the nearest one with "
      "MAPE ∝ time^-1/2 (the Monte Carlo rate; it ignores the reference's own noise floor).\n\n"
      "| N | budget | method | MAPE | render time (spp) | path tracer to that MAPE | path tracer / render |\n"
      "| ---: | ---: | --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& [key, m] : means) {
    const auto& [n, budget, method] = key;
    const auto pt = path_tracing_time_to(rows, m.of(m.mape));
    md += "| " + std::to_string(n) + " | " + budget_label(budget) + " | " + method + " | " + g(m.of(m.mape)) + " | " +
          seconds_text(m.of(m.render_seconds)) + " (" + std::to_string(m.spp) + ") | " + (pt.extrapolated ? "≈ " : "") +
          seconds_text(pt.seconds) + " | " + g(pt.seconds / m.of(m.render_seconds), "%.3g×") + " |\n";
  }
  return md;
}

}  // namespace clr::sweep
