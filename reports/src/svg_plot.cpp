#include "owval/reports/svg_plot.hpp"
#include "owval/base/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace owval::reports {
namespace {

constexpr const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd"};
constexpr double kLeft = 70, kRight = 20, kTop = 30, kBottom = 45;

struct Range {
  double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
  void Add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  void Widen() {
    if (lo > hi) lo = 0, hi = 1;
    if (hi == lo) lo -= 0.5, hi += 0.5;
  }
};

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string SvgLinePlot(const std::vector<Series>& series, const PlotOptions& o) {
  auto ty = [&](double y) { return o.log_y ? std::log10(y) : y; };
  Range xr, yr;
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (o.log_y && !(s.y[i] > 0)) continue;
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      xr.Add(s.x[i]);
      yr.Add(ty(s.y[i]));
    }
  xr.Widen();
  yr.Widen();
  const double w = o.width_px - kLeft - kRight, h = o.height_px - kTop - kBottom;
  auto px = [&](double x) { return kLeft + (x - xr.lo) / (xr.hi - xr.lo) * w; };
  auto py = [&](double y) { return kTop + h - (ty(y) - yr.lo) / (yr.hi - yr.lo) * h; };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.width_px << "\" height=\""
      << o.height_px << "\" viewBox=\"0 0 " << o.width_px << " " << o.height_px
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << o.width_px / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">"
      << Escape(o.title) << "</text>\n";
  svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << w << "\" height=\"" << h
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (int i = 0; i <= 4; ++i) {
    const double xv = xr.lo + (xr.hi - xr.lo) * i / 4, yv = yr.lo + (yr.hi - yr.lo) * i / 4;
    svg << "<text x=\"" << kLeft + w * i / 4 << "\" y=\"" << kTop + h + 16
        << "\" text-anchor=\"middle\">" << FormatNumber(xv, 4) << "</text>\n";
    svg << "<text x=\"" << kLeft - 6 << "\" y=\"" << kTop + h - h * i / 4 + 4
        << "\" text-anchor=\"end\">" << FormatNumber(o.log_y ? std::pow(10, yv) : yv, 4)
        << "</text>\n";
  }
  svg << "<text x=\"" << kLeft + w / 2 << "\" y=\"" << o.height_px - 8
      << "\" text-anchor=\"middle\">" << Escape(o.x_label) << "</text>\n";
  svg << "<text transform=\"translate(14," << kTop + h / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << Escape(o.y_label) << "</text>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const std::string colour = s.colour.empty() ? kPalette[k % 5] : s.colour;
    svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.2\" points=\"";
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if ((o.log_y && !(s.y[i] > 0)) || !std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      svg << FormatNumber(px(s.x[i]), 4) << "," << FormatNumber(py(s.y[i]), 4) << " ";
    }
    svg << "\"/>\n";
  }
  // The legend last, on a white box, so no line is drawn over it.
  std::size_t longest = 0;
  for (const Series& s : series) longest = std::max(longest, s.name.size());
  svg << "<rect x=\"" << kLeft + 4 << "\" y=\"" << kTop + 4 << "\" width=\"" << 16 + 7 * longest
      << "\" height=\"" << 6 + 14 * series.size()
      << "\" fill=\"white\" fill-opacity=\"0.9\" stroke=\"#bbb\"/>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const std::string colour = series[k].colour.empty() ? kPalette[k % 5] : series[k].colour;
    svg << "<text x=\"" << kLeft + 10 << "\" y=\"" << kTop + 16 + 14 * k << "\" fill=\"" << colour
        << "\">" << Escape(series[k].name) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace owval::reports
