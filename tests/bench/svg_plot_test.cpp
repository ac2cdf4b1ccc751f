// Tests of svgLinePlot's log axes, palette choice and dashes, and of svgBarChart's bar geometry.
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

TEST(SvgPlotTest, BarsStandInTheirGroupsAtTheirHeight) {
  // The plot is 420 x 300 px from (70, 40). Two groups of two bars: each group a 210 px slot whose
  // bars fill 80% of it, 84 px each. 50 of 100 is half the plot's height: from y = 190 down to 340.
  const std::string svg = svgBarChart("t", "y", {"a", "b"}, {{"first", {50.0, 100.0}}, {"second", {25.0, 0.0}}}, 100.0, 20.0, 60.0);
  EXPECT_NE(svg.find("<rect x=\"91\" y=\"190\" width=\"77.28\" height=\"150\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("<rect x=\"175\" y=\"265\" width=\"77.28\" height=\"75\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("<rect x=\"301\" y=\"40\" width=\"77.28\" height=\"300\""), std::string::npos) << svg;
  // The mark at 60: 40% down the plot.
  EXPECT_NE(svg.find("y1=\"160\" y2=\"160\" stroke=\"#444\" stroke-dasharray"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">first a: 50</title>"), std::string::npos) << svg;
}

}  // namespace
}  // namespace dentsim::bench
