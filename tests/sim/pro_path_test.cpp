// ProPath: the professional's tool poses recovered from pen readings and rendered forces, interpolated in time, and the nearest pose found.
#include <gtest/gtest.h>

#include "sim/pro_path.h"
#include "sim/sim_fixtures.h"
#include "sim/sim_params.h"

namespace dentsim {
namespace {

using test::straightStroke;

TEST(ProPath, ToolStandsWhereTheRenderedForceSaysAndIsSampledAHundredTimesASecond) {
  auto path = ProPath::fromSession(straightStroke(), "stroke");
  ASSERT_TRUE(path) << path.message();
  // Steps 0, 10, ..., 100: eleven poses, 0.01 s apart.
  ASSERT_EQ(path->poses().size(), 11u);
  EXPECT_DOUBLE_EQ(path->durationS(), 0.1);
  const ProPose& p = path->poses()[3];
  EXPECT_DOUBLE_EQ(p.t_s, 0.03);
  EXPECT_NEAR(p.drill.position.x, 0.3, 1e-12);
  EXPECT_NEAR(p.drill.position.z, 2.0, 1e-12);  // 2 N over 1 N/mm
  EXPECT_TRUE(p.drill_held);
  EXPECT_FALSE(p.mirror_held);
  // A stiffer coupling: the same force is a smaller offset (2 N over 4 N/mm).
  auto stiff = ProPath::fromSession(straightStroke(4.0), "stroke");
  ASSERT_TRUE(stiff);
  EXPECT_NEAR(stiff->poses()[3].drill.position.z, 0.5, 1e-12);
}

TEST(ProPath, InterpolatesBetweenSamplesAndHoldsTheEnds) {
  auto path = ProPath::fromSession(straightStroke(), "stroke");
  ASSERT_TRUE(path);
  EXPECT_NEAR(path->at(0.025).drill.position.x, 0.25, 1e-12);
  EXPECT_NEAR(path->at(-1.0).drill.position.x, 0.0, 1e-12);
  EXPECT_NEAR(path->at(5.0).drill.position.x, 1.0, 1e-12);
}

TEST(ProPath, NearestPoseSearchesOnlyItsWindow) {
  auto path = ProPath::fromSession(straightStroke(), "stroke");
  ASSERT_TRUE(path);
  // (0.52, 1, 2) is nearest to the pose at x = 0.5, index 5.
  EXPECT_EQ(path->nearestDrill({0.52, 1.0, 2.0}), 5u);
  // From index 7 on, the nearest is the window's first pose.
  EXPECT_EQ(path->nearestDrill({0.52, 1.0, 2.0}, 7), 7u);
  // A window of three poses from index 0 ends at index 2.
  EXPECT_EQ(path->nearestDrill({0.52, 1.0, 2.0}, 0, 3), 2u);
}

TEST(ProPath, RefusesASessionWithoutADrillReading) {
  SessionRecording s = straightStroke();
  for (SessionStep& step : s.steps) step.pens = 0;
  auto path = ProPath::fromSession(s, "empty.dses");
  ASSERT_FALSE(path);
  EXPECT_NE(path.message().find("empty.dses"), std::string::npos);
  EXPECT_NE(path.message().find("no drill reading"), std::string::npos);
}

}  // namespace
}  // namespace dentsim
