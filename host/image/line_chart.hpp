#pragma once
// Line charts as SVG: the figures a run or a benchmark writes beside its numbers (a training's convergence). SVG is
// text, so no plotting library (matplotlib, a font rasteriser) is needed wherever the binary runs, and every
// browser and GitHub shows it.
#include <string>
#include <vector>

namespace clr::image {

struct ChartSeries {
  std::string label;
  std::vector<double> x, y;  // equal lengths; points with a non-finite coordinate (or y ≤ 0 on a log axis) are skipped
};

struct ChartPanel {
  std::string title, x_label, y_label;
  bool log_y = true;
  std::vector<ChartSeries> series;
};

// Panels side by side under `title`, each with its axes, ticks and a legend; series keep their colour across
// panels (the i-th series of every panel shares one), so one quantity reads the same everywhere.
std::string line_chart_svg(const std::string& title, const std::vector<ChartPanel>& panels);

}  // namespace clr::image
