// Minimal SVG line plots for the benchmark reports (no plotting library in Debian's C++ stack fits).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace dentsim::bench {

struct PlotSeries {
  std::string name;                               // legend text
  std::vector<std::pair<double, double>> points;  // (x, y), drawn in order
  int colour = -1;                                // palette index (0..5); -1: the series' position
  std::string dash{};                             // SVG stroke-dasharray ("6,4"); empty: solid
};

// An 640x400 SVG with axes, ticks at each distinct x, a legend, and log10 axes where asked
// (points at or below 0 on a log axis are left out).
std::string svgLinePlot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<PlotSeries>& series, bool log_y, bool log_x = false);

struct BarSeries {
  std::string name;             // legend text
  std::vector<double> values;   // one per category, >= 0
};

// A 640x400 SVG of grouped bars: one group per category (left to right), one bar per series in
// each group, a y axis from 0 to y_max with ticks every y_tick, a dashed line at `mark` (< 0: none)
// named in the legend by `mark_label`, and a legend.
std::string svgBarChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                        const std::vector<BarSeries>& series, double y_max, double y_tick, double mark = -1.0,
                        const std::string& mark_label = "");

}  // namespace dentsim::bench
