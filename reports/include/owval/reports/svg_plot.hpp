#pragma once
// Line plots as standalone SVG text, for reports and fit histories: no plotting dependency, and
// the output embeds directly in the HTML report.
#include <string>
#include <vector>

namespace owval::reports {

struct Series {
  std::string name;
  std::vector<double> x, y;
  std::string colour = "";  // empty: picked from a palette
};

struct PlotOptions {
  std::string title;
  std::string x_label, y_label;
  bool log_y = false;  // non-positive values are dropped on a log axis
  int width_px = 640, height_px = 360;
};

std::string SvgLinePlot(const std::vector<Series>& series, const PlotOptions& options);

}  // namespace owval::reports
