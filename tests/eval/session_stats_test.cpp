// Tests of sessionStats on sessions built in memory: elapsed time, contact samples, force and tilt over their thresholds.
#include "eval/session_stats.h"

#include <gtest/gtest.h>

#include <numbers>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A step with a drill reading: `contacts` shell points inside tissue, force f, grip rotated by q.
SessionStep drillStep(uint64_t k, uint32_t contacts, Vec3 force, Quat q = {}) {
  SessionStep s;
  s.step = k;
  s.pens = 1;  // drill only
  s.reading[0].grip = Pose{{0, 0, 10}, q};
  s.contacts[0] = contacts;
  s.force_n[0] = force;
  return s;
}

TEST(SessionStats, EmptySessionHasNothing) {
  SessionRecording r;
  const SessionStats s = sessionStats(r, test::cavityTask());
  EXPECT_EQ(s.steps, 0u);
  EXPECT_EQ(s.elapsed_s, 0.0);
  EXPECT_EQ(s.contact_samples, 0u);
}

TEST(SessionStats, CountsContactForceAndTilt) {
  SessionRecording r;
  r.info.rate_hz = 1000;
  // 0: contacts but no drill reading (a mirror-only step): not in contact.
  SessionStep mirror_only = drillStep(0, 4, {0, 0, 9});
  mirror_only.pens = 2;
  r.steps.push_back(mirror_only);
  r.steps.push_back(drillStep(1, 3, {0, 0, 2}));                   // contact, 2 N: fine
  r.steps.push_back(drillStep(2, 3, {3, 4, 0}));                   // contact, |f| = 5 N > 3 N
  r.steps.push_back(drillStep(3, 1, {0, 0, 3}));                   // exactly 3 N: not over
  r.steps.push_back(drillStep(4, 2, {0, 0, 1}, Quat::fromAxisAngle({1, 0, 0}, 20 * kDeg)));  // tilted 20 deg > 10
  r.steps.push_back(drillStep(5, 2, {0, 0, 1}, Quat::fromAxisAngle({0, 1, 0}, 9 * kDeg)));   // 9 deg: fine
  r.steps.push_back(drillStep(6, 0, {0, 0, 50}, Quat::fromAxisAngle({1, 0, 0}, 90 * kDeg))); // no contact
  r.gaps.push_back({7, 3});                                        // three steps lost: they still took time
  const SessionStats s = sessionStats(r, test::cavityTask());
  EXPECT_EQ(s.steps, 7u);
  EXPECT_EQ(s.lost_steps, 3u);
  EXPECT_DOUBLE_EQ(s.elapsed_s, 0.010);
  EXPECT_EQ(s.contact_samples, 5u);
  EXPECT_EQ(s.force_over, 1u);
  EXPECT_EQ(s.parallel_over, 1u);
  EXPECT_DOUBLE_EQ(s.max_force_n, 5.0);
  EXPECT_NEAR(s.max_tilt_deg, 20.0, 1e-9);
}

TEST(SessionStats, TiltIsMeasuredAgainstTheTasksAxis) {
  // The grip's +z is the bur axis (the tip points along -z).
  EXPECT_NEAR(burTiltDeg(Pose{}, {0, 0, 1}), 0.0, 1e-12);
  EXPECT_NEAR(burTiltDeg(Pose{{}, Quat::fromAxisAngle({0, 1, 0}, 30 * kDeg)}, {0, 0, 1}), 30.0, 1e-9);
  EXPECT_NEAR(burTiltDeg(Pose{}, {0, 0, -1}), 180.0, 1e-12);  // upside down is the worst tilt
  // A task whose axis leans 30 degrees toward +x: the grip rotated the same way is parallel.
  Task task = test::cavityTask();
  task.insertion_axis = normalized(Vec3{std::sin(30 * kDeg), 0, std::cos(30 * kDeg)});
  SessionRecording r;
  r.info.rate_hz = 1000;
  r.steps.push_back(drillStep(0, 1, {}, Quat::fromAxisAngle({0, 1, 0}, 30 * kDeg)));
  r.steps.push_back(drillStep(1, 1, {}));
  const SessionStats s = sessionStats(r, task);
  EXPECT_EQ(s.parallel_over, 1u);  // the upright step, 30 degrees off
  EXPECT_NEAR(s.max_tilt_deg, 30.0, 1e-9);
}

}  // namespace
}  // namespace dentsim
