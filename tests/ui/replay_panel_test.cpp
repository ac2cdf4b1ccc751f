// The replay timeline's columns: the largest force of each column's steps, contact where the drill was in tissue, and over the threshold only in contact, as the score counts it; the speeds and the clock.
#include "ui/replay_panel.h"

#include <gtest/gtest.h>

#include <vector>

namespace dentsim::ui {
namespace {

SessionStep step(double force_n, uint32_t contacts, bool reading = true) {
  SessionStep s;
  s.pens = reading ? 1u : 0u;
  s.force_n[0] = Vec3{0.0, force_n * 0.6, force_n * 0.8};  // |force| = force_n
  s.contacts[0] = contacts;
  return s;
}

TEST(ReplayPanel, EachColumnKeepsTheLargestForceOfItsStepsAndMarksContactAndForceOverTheThreshold) {
  // 8 steps in 4 columns of 2: a spike in column 1, a heavy step without contact in column 2, a
  // heavy step in contact in column 3.
  const std::vector<SessionStep> steps = {step(0.0, 0), step(0.0, 0), step(1.0, 2), step(2.5, 3),
                                          step(5.0, 0), step(0.5, 0), step(0.5, 1), step(4.0, 5)};
  const std::vector<ForceColumn> c = forceColumns(steps, 3.0, 4);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_FLOAT_EQ(c[0].max_force_n, 0.0f);
  EXPECT_FALSE(c[0].contact);
  EXPECT_FLOAT_EQ(c[1].max_force_n, 2.5f);
  EXPECT_TRUE(c[1].contact);
  EXPECT_FALSE(c[1].over);
  EXPECT_FLOAT_EQ(c[2].max_force_n, 5.0f);
  EXPECT_FALSE(c[2].contact);
  EXPECT_FALSE(c[2].over) << "a force out of contact is no error (session_stats' force_over)";
  EXPECT_FLOAT_EQ(c[3].max_force_n, 4.0f);
  EXPECT_TRUE(c[3].over);
}

TEST(ReplayPanel, MoreColumnsThanStepsLeaveColumnsEmptyAndAStepWithoutAReadingIsNotInContact) {
  const std::vector<SessionStep> steps = {step(4.0, 2, false), step(4.0, 2)};
  const std::vector<ForceColumn> c = forceColumns(steps, 3.0, 5);
  ASSERT_EQ(c.size(), 5u);
  int contact = 0, over = 0;
  for (const ForceColumn& col : c) {
    contact += col.contact ? 1 : 0;
    over += col.over ? 1 : 0;
  }
  EXPECT_EQ(contact, 1);
  EXPECT_EQ(over, 1);
  EXPECT_EQ(forceColumns({}, 3.0, 0).size(), 1u);
}

TEST(ReplayPanel, TheSpeedsAndTheClock) {
  EXPECT_EQ(replaySpeedIndex(0.25), 0);
  EXPECT_EQ(replaySpeedIndex(8.0), 5);
  EXPECT_FALSE(replaySpeedIndex(3.0).has_value());
  EXPECT_EQ(replayClock(0.0), "0:00.0");
  EXPECT_EQ(replayClock(65.34), "1:05.3");
  EXPECT_EQ(replayClock(-1.0), "0:00.0");
}

}  // namespace
}  // namespace dentsim::ui
