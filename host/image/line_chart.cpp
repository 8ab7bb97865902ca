#include "image/line_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace clr::image {
namespace {

constexpr double kPanelWidth = 440, kPanelHeight = 320;
constexpr double kLeft = 72, kRight = 16, kTop = 34, kBottom = 46;  // the plot area's margins in a panel
constexpr double kTitleHeight = 28;
// Colour-blind-safe (Okabe–Ito), in the order series are given.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// Ticks of a linear axis over [lo, hi]: steps of 1, 2 or 5 × 10^k, about five of them.
std::vector<double> linear_ticks(double lo, double hi) {
  const double raw = (hi - lo) / 5;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) ticks.push_back(t);
  return ticks;
}

// Ticks of a log axis over [lo, hi]: the decades, and 2 and 5 times them where the axis spans less than two.
std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> ticks;
  const bool fine = std::log10(hi / lo) < 2;
  for (double decade = std::pow(10.0, std::floor(std::log10(lo))); decade <= hi; decade *= 10)
    for (double m : fine ? std::vector<double>{1, 2, 5} : std::vector<double>{1})
      if (m * decade >= lo && m * decade <= hi) ticks.push_back(m * decade);
  return ticks;
}

bool usable(double x, double y, bool log_y) { return std::isfinite(x) && std::isfinite(y) && (!log_y || y > 0); }

void panel_svg(std::string& svg, const ChartPanel& p, double left, double top) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : p.series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i], p.log_y)) {
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
      }
  const double w = kPanelWidth - kLeft - kRight, h = kPanelHeight - kTop - kBottom;
  const double px = left + kLeft, py = top + kTop;
  char buf[512];
  std::snprintf(buf, sizeof buf, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"13\">", px + w / 2,
                top + 20);
  svg += buf + escaped(p.title) + "</text>\n";
  std::snprintf(buf, sizeof buf,
                "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#444\"/>\n", px, py,
                w, h);
  svg += buf;
  if (!(x0 <= x1)) {  // no point to draw: the frame and a note
    std::snprintf(buf, sizeof buf,
                  "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"12\">no data</text>\n", px + w / 2,
                  py + h / 2);
    svg += buf;
    return;
  }
  // A single value still needs an axis of some length.
  if (x1 == x0) x0 -= 0.5, x1 += 0.5;
  if (p.log_y) {
    y0 = std::pow(10.0, std::floor(std::log10(y0) * 4) / 4), y1 = std::pow(10.0, std::ceil(std::log10(y1) * 4) / 4);
    if (y1 <= y0) y0 /= 2, y1 *= 2;
  } else {
    if (y1 == y0) y0 -= 0.5, y1 += 0.5;
  }
  const auto sx = [&](double x) { return px + (x - x0) / (x1 - x0) * w; };
  const auto sy = [&](double y) {
    const double t = p.log_y ? std::log(y / y0) / std::log(y1 / y0) : (y - y0) / (y1 - y0);
    return py + h - t * h;
  };
  for (double t : linear_ticks(x0, x1)) {
    std::snprintf(buf, sizeof buf,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"11\">%s</text>\n",
                  sx(t), py, sx(t), py + h, sx(t), py + h + 15, number(t).c_str());
    svg += buf;
  }
  for (double t : p.log_y ? log_ticks(y0, y1) : linear_ticks(y0, y1)) {
    std::snprintf(buf, sizeof buf,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\" font-size=\"11\">%s</text>\n",
                  px, sy(t), px + w, sy(t), px - 5, sy(t) + 4, number(t).c_str());
    svg += buf;
  }
  std::snprintf(buf, sizeof buf,
                "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"12\">%s</text>\n"
                "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"12\" "
                "transform=\"rotate(-90 %.1f %.1f)\">%s</text>\n",
                px + w / 2, py + h + 34, escaped(p.x_label).c_str(), left + 16, py + h / 2, left + 16, py + h / 2,
                escaped(p.y_label + (p.log_y ? " (log)" : "")).c_str());
  svg += buf;
  for (std::size_t k = 0; k < p.series.size(); ++k) {
    const auto& s = p.series[k];
    const char* colour = kColours[k % std::size(kColours)];
    std::string points;
    std::size_t drawn = 0;
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i], p.log_y)) {
        std::snprintf(buf, sizeof buf, "%.1f,%.1f ", sx(s.x[i]), sy(s.y[i]));
        points += buf;
        std::snprintf(buf, sizeof buf, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"%s\"/>\n", sx(s.x[i]),
                      sy(s.y[i]), colour);
        svg += buf;
        ++drawn;
      }
    if (drawn > 1)
      svg += "<polyline fill=\"none\" stroke-width=\"1.5\" stroke=\"" + std::string(colour) + "\" points=\"" + points +
             "\"/>\n";
    std::snprintf(buf, sizeof buf,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\">%s</text>\n",
                  px + w - 120, py + 14 + 15 * double(k), px + w - 100, py + 14 + 15 * double(k), colour, px + w - 95,
                  py + 18 + 15 * double(k), escaped(s.label).c_str());
    svg += buf;
  }
}

}  // namespace

std::string line_chart_svg(const std::string& title, const std::vector<ChartPanel>& panels) {
  const double width = kPanelWidth * double(std::max<std::size_t>(1, panels.size()));
  const double height = kTitleHeight + kPanelHeight;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
                "font-family=\"sans-serif\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
                "<text x=\"%.1f\" y=\"20\" text-anchor=\"middle\" font-size=\"15\">",
                width, height, width, height, width / 2);
  std::string svg = buf + escaped(title) + "</text>\n";
  for (std::size_t i = 0; i < panels.size(); ++i) panel_svg(svg, panels[i], kPanelWidth * double(i), kTitleHeight);
  svg += "</svg>\n";
  return svg;
}

}  // namespace clr::image
