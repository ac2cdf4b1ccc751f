// Tests of svgLinePlot's log axes, palette choice and dashes.
#include "bench/svg_plot.h"

#include <gtest/gtest.h>

namespace dentsim::bench {
namespace {

TEST(SvgPlotTest, LogXPutsDecadesAtEqualSteps) {
  // x = 10, 100, 1000 on a log axis: the middle point sits halfway between the ends, at
  // 80 + 0.5 x (640 - 80 - 190) = 265 px.
  const PlotSeries s{"a", {{10.0, 1.0}, {100.0, 10.0}, {1000.0, 100.0}}};
  const std::string svg = svgLinePlot("t", "x", "y", {s}, /*log_y=*/true, /*log_x=*/true);
  EXPECT_NE(svg.find("<circle cx=\"265\""), std::string::npos) << svg;
}

TEST(SvgPlotTest, ZeroIsLeftOutOnALogAxis) {
  const PlotSeries s{"a", {{0.0, 1.0}, {10.0, 2.0}, {100.0, 3.0}}};
  const std::string svg = svgLinePlot("t", "x", "y", {s}, false, /*log_x=*/true);
  EXPECT_EQ(svg.find("nan"), std::string::npos) << svg;
  EXPECT_EQ(svg.find("inf"), std::string::npos) << svg;
}

TEST(SvgPlotTest, ColourAndDashAreThoseAsked) {
  const PlotSeries solid{"ours", {{1.0, 1.0}, {2.0, 2.0}}, 2, ""};
  const PlotSeries dashed{"peer", {{1.0, 2.0}, {2.0, 3.0}}, 2, "7,4"};
  const std::string svg = svgLinePlot("t", "x", "y", {solid, dashed}, false);
  // Both take palette entry 2 (green) rather than their positions; only the second is dashed, in its
  // line and its legend swatch.
  EXPECT_EQ(svg.find("#1f77b4"), std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#2ca02c\" stroke-width"), std::string::npos);
  size_t dashes = 0;
  for (size_t at = svg.find("stroke-dasharray=\"7,4\""); at != std::string::npos;
       at = svg.find("stroke-dasharray=\"7,4\"", at + 1))
    ++dashes;
  EXPECT_EQ(dashes, 2u);
}

}  // namespace
}  // namespace dentsim::bench
