// SVG line plots: scales, axes, ticks, polylines and a legend.
#include "bench/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

namespace dentsim::bench {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::string svgLinePlot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<PlotSeries>& series, bool log_y, bool log_x) {
  constexpr double kW = 640, kH = 400, kLeft = 80, kRight = 190, kTop = 40, kBottom = 60;
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};
  std::set<double> xs;
  double ymin = HUGE_VAL, ymax = -HUGE_VAL;
  auto shown = [&](double x, double y) { return (!log_y || y > 0) && (!log_x || x > 0); };
  for (const auto& s : series)
    for (auto [x, y] : s.points) {
      if (!shown(x, y)) continue;
      xs.insert(x);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  if (xs.empty()) { xs.insert(1); ymin = 1; ymax = 10; }  // nothing to draw: any range valid on log axes too
  auto ty = [&](double y) { return log_y ? std::log10(y) : y; };
  double lo = ty(ymin), hi = ty(ymax);
  if (log_y) { lo = std::floor(lo); hi = std::ceil(hi); }
  if (hi - lo < 1e-12) { lo -= 1; hi += 1; }
  if (!log_y) lo = std::min(lo, 0.0);
  auto tx = [&](double x) { return log_x ? std::log10(x) : x; };
  const double xlo = tx(*xs.begin()), xhi = tx(*xs.rbegin()) == xlo ? xlo + 1 : tx(*xs.rbegin());
  auto px = [&](double x) { return kLeft + (tx(x) - xlo) / (xhi - xlo) * (kW - kLeft - kRight); };
  auto py = [&](double y) { return kH - kBottom - (ty(y) - lo) / (hi - lo) * (kH - kTop - kBottom); };

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kW << "\" height=\"" << kH
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << kW / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << escape(title) << "</text>\n";
  o << "<line x1=\"" << kLeft << "\" y1=\"" << kH - kBottom << "\" x2=\"" << kW - kRight << "\" y2=\"" << kH - kBottom
    << "\" stroke=\"black\"/>\n<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\""
    << kH - kBottom << "\" stroke=\"black\"/>\n";
  for (double x : xs)
    o << "<text x=\"" << px(x) << "\" y=\"" << kH - kBottom + 18 << "\" text-anchor=\"middle\">" << number(x) << "</text>\n";
  const int ticks = log_y ? int(hi - lo) : 5;
  for (int i = 0; i <= ticks; ++i) {
    const double t = lo + (hi - lo) * i / ticks;
    const double v = log_y ? std::pow(10.0, t) : t;
    const double y = kH - kBottom - (t - lo) / (hi - lo) * (kH - kTop - kBottom);
    o << "<line x1=\"" << kLeft - 4 << "\" y1=\"" << y << "\" x2=\"" << kW - kRight << "\" y2=\"" << y
      << "\" stroke=\"#ddd\"/>\n<text x=\"" << kLeft - 8 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">" << number(v)
      << "</text>\n";
  }
  o << "<text x=\"" << (kLeft + kW - kRight) / 2 << "\" y=\"" << kH - 15 << "\" text-anchor=\"middle\">" << escape(x_label)
    << "</text>\n<text transform=\"translate(18," << (kTop + kH - kBottom) / 2
    << ") rotate(-90)\" text-anchor=\"middle\">" << escape(y_label) << "</text>\n";
  for (size_t i = 0; i < series.size(); ++i) {
    const char* c = colours[(series[i].colour >= 0 ? size_t(series[i].colour) : i) % 6];
    const std::string dash = series[i].dash.empty() ? "" : " stroke-dasharray=\"" + series[i].dash + "\"";
    o << "<polyline fill=\"none\" stroke=\"" << c << "\"" << dash << " stroke-width=\"2\" points=\"";
    for (auto [x, y] : series[i].points)
      if (shown(x, y)) o << px(x) << "," << py(y) << " ";
    o << "\"/>\n";
    for (auto [x, y] : series[i].points)
      if (shown(x, y)) o << "<circle cx=\"" << px(x) << "\" cy=\"" << py(y) << "\" r=\"3\" fill=\"" << c << "\"/>\n";
    const double ly = kTop + 10 + 20.0 * double(i);
    o << "<line x1=\"" << kW - kRight + 10 << "\" y1=\"" << ly << "\" x2=\"" << kW - kRight + 30 << "\" y2=\"" << ly
      << "\" stroke=\"" << c << "\"" << dash << " stroke-width=\"2\"/>\n<text x=\"" << kW - kRight + 35 << "\" y=\"" << ly + 4 << "\">"
      << escape(series[i].name) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string svgBarChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                        const std::vector<BarSeries>& series, double y_max, double y_tick, double mark,
                        const std::string& mark_label) {
  constexpr double kW = 640, kH = 400, kLeft = 70, kRight = 150, kTop = 40, kBottom = 60;
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};
  const double plot_w = kW - kLeft - kRight, plot_h = kH - kTop - kBottom;
  auto py = [&](double y) { return kTop + plot_h * (1.0 - std::clamp(y / y_max, 0.0, 1.0)); };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kW << "\" height=\"" << kH << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << kW / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << escape(title) << "</text>\n";
  // The y axis and its ticks.
  for (double y = 0.0; y <= y_max + 1e-9; y += y_tick) {
    o << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + plot_w << "\" y1=\"" << py(y) << "\" y2=\"" << py(y)
      << "\" stroke=\"#ddd\"/>\n";
    o << "<text x=\"" << kLeft - 6 << "\" y=\"" << py(y) + 4 << "\" text-anchor=\"end\">" << number(y) << "</text>\n";
  }
  o << "<text transform=\"translate(18," << kTop + plot_h / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << escape(y_label)
    << "</text>\n";
  // The bars: each group takes an equal slot, its bars 80% of it.
  const double slot = categories.empty() ? plot_w : plot_w / double(categories.size());
  const double bar = series.empty() ? 0.0 : 0.8 * slot / double(series.size());
  for (size_t c = 0; c < categories.size(); ++c) {
    const double x0 = kLeft + slot * double(c) + 0.1 * slot;
    for (size_t k = 0; k < series.size(); ++k) {
      const double v = c < series[k].values.size() ? series[k].values[c] : 0.0;
      o << "<rect x=\"" << x0 + bar * double(k) << "\" y=\"" << py(v) << "\" width=\"" << bar * 0.92 << "\" height=\""
        << kTop + plot_h - py(v) << "\" fill=\"" << colours[k % 6] << "\"><title>" << escape(series[k].name) << " "
        << escape(categories[c]) << ": " << number(v) << "</title></rect>\n";
    }
    o << "<text x=\"" << kLeft + slot * (double(c) + 0.5) << "\" y=\"" << kTop + plot_h + 18 << "\" text-anchor=\"middle\">"
      << escape(categories[c]) << "</text>\n";
  }
  if (mark >= 0)
    o << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + plot_w << "\" y1=\"" << py(mark) << "\" y2=\"" << py(mark)
      << "\" stroke=\"#444\" stroke-dasharray=\"6,4\"/>\n";
  o << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft << "\" y1=\"" << kTop << "\" y2=\"" << kTop + plot_h << "\" stroke=\"black\"/>\n";
  o << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + plot_w << "\" y1=\"" << kTop + plot_h << "\" y2=\"" << kTop + plot_h
    << "\" stroke=\"black\"/>\n";
  for (size_t k = 0; k < series.size(); ++k) {
    const double ly = kTop + 10 + 20 * double(k);
    o << "<rect x=\"" << kW - kRight + 15 << "\" y=\"" << ly - 9 << "\" width=\"12\" height=\"12\" fill=\"" << colours[k % 6] << "\"/>\n";
    o << "<text x=\"" << kW - kRight + 33 << "\" y=\"" << ly + 2 << "\">" << escape(series[k].name) << "</text>\n";
  }
  if (mark >= 0 && !mark_label.empty()) {
    const double ly = kTop + 10 + 20 * double(series.size());
    o << "<line x1=\"" << kW - kRight + 15 << "\" x2=\"" << kW - kRight + 27 << "\" y1=\"" << ly - 3 << "\" y2=\"" << ly - 3
      << "\" stroke=\"#444\" stroke-dasharray=\"3,2\"/>\n";
    o << "<text x=\"" << kW - kRight + 33 << "\" y=\"" << ly + 2 << "\">" << escape(mark_label) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace dentsim::bench
