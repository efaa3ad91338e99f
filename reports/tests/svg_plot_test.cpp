#include "owval/reports/svg_plot.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <sstream>

namespace owval::reports {
namespace {

std::vector<std::pair<double, double>> Points(const std::string& svg) {
  std::vector<std::pair<double, double>> points;
  const std::regex polyline("points=\"([^\"]*)\"");
  std::smatch m;
  if (!std::regex_search(svg, m, polyline)) return points;
  std::istringstream in(m[1].str());
  std::string pair;
  while (in >> pair) {
    const auto comma = pair.find(',');
    points.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
  }
  return points;
}

TEST(SvgPlot, PolylineHasOnePointPerSampleInsideThePlotArea) {
  PlotOptions o;
  o.title = "loss";
  const std::string svg = SvgLinePlot({{"loss", {0, 1, 2, 3}, {4, 3, 1, 0.5}}}, o);
  const auto points = Points(svg);
  ASSERT_EQ(points.size(), 4u);
  for (const auto& [x, y] : points) {
    EXPECT_GE(x, 0);
    EXPECT_LE(x, o.width_px);
    EXPECT_GE(y, 0);
    EXPECT_LE(y, o.height_px);
  }
  EXPECT_LT(points.front().first, points.back().first);
  EXPECT_LT(points.front().second, points.back().second);  // larger value drawn higher (smaller y)
}

TEST(SvgPlot, LogAxisDropsNonPositiveValues) {
  PlotOptions o;
  o.log_y = true;
  EXPECT_EQ(Points(SvgLinePlot({{"l", {0, 1, 2}, {1, 0, 1e-3}}}, o)).size(), 2u);
}

TEST(SvgPlot, EscapesText) {
  PlotOptions o;
  o.title = "a<b";
  EXPECT_NE(SvgLinePlot({}, o).find("a&lt;b"), std::string::npos);
}

}  // namespace
}  // namespace owval::reports
