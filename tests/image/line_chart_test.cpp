// The SVG line charts that runs write beside their numbers (convergence.svg).
#include "image/line_chart.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace clr::image {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(LineChart, DrawsEachSeriesAndSkipsWhatALogAxisCannotShow) {
  ChartPanel panel{"p", "step", "error", true, {}};
  panel.series.push_back({"a <b>", {1, 2, 3}, {0.5, 0.25, 0.125}});
  panel.series.push_back({"c", {1, 2, 3, 4}, {0.1, 0.0, NAN, 0.05}});  // two points a log axis can show
  const std::string svg = line_chart_svg("t & u", {panel, panel});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_THAT(svg, HasSubstr("</svg>"));
  EXPECT_EQ(count(svg, "<polyline"), 4u) << "two series in each of two panels";
  EXPECT_EQ(count(svg, "<circle"), 2u * (3 + 2)) << "a zero or NaN value is no point on a log axis";
  EXPECT_THAT(svg, HasSubstr("a &lt;b&gt;"));
  EXPECT_THAT(svg, HasSubstr("t &amp; u"));
  EXPECT_THAT(svg, Not(HasSubstr("nan")));
}

TEST(LineChart, EmptyPanelSaysSo) {
  const std::string svg = line_chart_svg("t", {{"empty", "x", "y", true, {{"s", {1}, {-1}}}}});
  EXPECT_THAT(svg, HasSubstr("no data"));
  EXPECT_EQ(count(svg, "<polyline"), 0u);
}

}  // namespace
}  // namespace clr::image
