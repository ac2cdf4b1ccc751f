// Minimal SVG line plots for the benchmark reports (no plotting library in Debian's C++ stack fits).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace dentsim::bench {

struct PlotSeries {
  std::string name;                               // legend text
  std::vector<std::pair<double, double>> points;  // (x, y), drawn in order
};

// An 640x400 SVG with axes, ticks at each distinct x, a legend, and a log10 y axis if log_y.
std::string svgLinePlot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<PlotSeries>& series, bool log_y);

}  // namespace dentsim::bench
