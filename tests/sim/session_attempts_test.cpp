// Derived attempts: each attempt made from a professional's session by its one edit, checked on a hand-made session whose numbers can be followed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "io/pen_playback.h"
#include "sim/session_attempts.h"
#include "sim/sim_params.h"
#include "sim/tool_library.h"

namespace dentsim {
namespace {

// A professional over 2 s at 1 kHz (2001 steps), the bur upright (+z): still at (0, 0, 5) for the
// first 0.5 s, then cutting from (1, 0, 0) to (3, 0, 0) with the pedal down and contact, rendering
// (0, 0, 0.5) N (so the grip stood 0.5 mm below the bur at 1 N/mm), then still and lifted.
SessionRecording professional() {
  SessionRecording s;
  s.info.rate_hz = 1000.0;
  s.info.drill_tool = "round_bur_010";
  s.info.params_json = simParamsJson(defaultSimParams());
  for (uint64_t k = 0; k <= 2000; ++k) {
    SessionStep step;
    step.step = k;
    step.pens = 1;
    const double t = double(k) / 1000.0;
    const bool cutting = t >= 0.5 && t <= 1.5;
    const double x = t < 0.5 ? 0.0 : t <= 1.5 ? 1.0 + 2.0 * (t - 0.5) : 3.0;
    step.reading[0].grip.position = {x, 0.0, cutting ? 0.0 : 5.0};
    step.reading[0].pedal = cutting ? 1.0 : 0.0;
    step.contacts[0] = cutting ? 20 : 0;
    step.force_n[0] = cutting ? Vec3{0, 0, 0.5} : Vec3{};
    s.steps.push_back(step);
  }
  return s;
}

const ToothAxes kAxes;  // crown +z, mesial -x, buccal -y

PenReading at(const PenPath& path, double t) {
  ScriptedPen pen(path, PenRole::Drill);
  PenReading r;
  EXPECT_TRUE(pen.read(t, &r));
  return r;
}

double endOf(const PenPath& path) { return path.samples.empty() ? 0.0 : path.samples.back().t_s; }

TEST(SessionAttempts, TheProfessionalsCuttingIsFoundInTheSession) {
  auto pro = professionalPath(professional(), "pro");
  ASSERT_TRUE(pro.ok()) << pro.message();
  EXPECT_DOUBLE_EQ(pro->cut_start_s, 0.5);
  EXPECT_DOUBLE_EQ(pro->cut_end_s, 1.5);
  EXPECT_DOUBLE_EQ(pro->elapsed_s, 2.0);
  // The cutting grip runs from x 1 to 3: its mean is x 2.
  EXPECT_NEAR(pro->cut_centre.x, 2.0, 1e-9);
  // Every 5 ms: 401 drill samples, each with its press (-F / k: 0.5 mm down while cutting).
  ASSERT_EQ(pro->drill_press.size(), 401u);
  EXPECT_NEAR(pro->drill_press[200].z, -0.5, 1e-12);
  EXPECT_TRUE(pro->drill_cutting[200]);
  EXPECT_FALSE(pro->drill_cutting[0]);
}

TEST(SessionAttempts, ASessionThatNeverCutsHasNoAttempts) {
  SessionRecording s = professional();
  for (SessionStep& step : s.steps) step.contacts[0] = 0;
  auto pro = professionalPath(s, "pro.dses");
  ASSERT_FALSE(pro.ok());
  EXPECT_NE(pro.message().find("never cut"), std::string::npos) << pro.message();
}

TEST(SessionAttempts, EachFaultIsItsOneEdit) {
  DerivedAttemptSettings s;
  auto pro = professionalPath(professional(), "pro", s);
  ASSERT_TRUE(pro.ok());
  const Vec3 up{0, 0, 1};
  // The second careful hand: 1.15 times as long, within the tremor of the professional's path.
  const PenPath expert = derivedAttemptPath(*pro, Attempt::Expert, up, kAxes, s);
  EXPECT_NEAR(endOf(expert), 2.0 * s.pace_factor, 1e-9);
  const PenReading e = at(expert, 1.0 * s.pace_factor);
  EXPECT_NEAR(e.grip.position.x, 2.0, s.tremor_mm + 1e-9);
  EXPECT_NEAR(e.pedal, 1.0, 1e-12);
  // Under-cut without a removal curve: half of the cutting time, at 1.0 s, then out along the axis.
  const PenPath under = derivedAttemptPath(*pro, Attempt::Undercut, up, kAxes, s);
  EXPECT_NEAR(at(under, 1.0).grip.position.x, 2.0, 1e-9);
  EXPECT_NEAR(at(under, endOf(under)).grip.position.z, s.lift_mm, 1e-9);
  EXPECT_EQ(at(under, endOf(under)).pedal, 0.0);
  // With the professional's removal known, it stops where half was removed.
  ProfessionalPath known = *pro;
  known.half_removed_s = 0.75;
  const PenPath early = derivedAttemptPath(known, Attempt::Undercut, up, kAxes, s);
  EXPECT_NEAR(at(early, endOf(early)).grip.position.x, 1.5, 1e-9);
  // Token: 0.3 s after the first cut.
  const PenPath token = derivedAttemptPath(*pro, Attempt::Token, up, kAxes, s);
  EXPECT_NEAR(at(token, endOf(token)).grip.position.x, 1.6, 1e-9);
  // Slow: three times as long, the pedal as the professional held it while working, and at every
  // moment either where the professional was or holding still with the turbine stopped.
  const PenPath slow = derivedAttemptPath(*pro, Attempt::Slow, up, kAxes, s);
  EXPECT_NEAR(endOf(slow), 3.0 * 2.0, 1e-3);  // its last hold ends 0.1 ms short
  EXPECT_NEAR(at(slow, 0.75).grip.position.x, 1.5, 1e-9);   // the first piece's work, unchanged
  EXPECT_EQ(at(slow, 1.5).pedal, 0.0);                        // its pause
  EXPECT_NEAR(at(slow, 1.5).grip.position.x, 2.0, 1e-9);      // held where the piece ended
  EXPECT_NEAR(at(slow, 3.25).grip.position.x, 2.5, 1e-9);     // 1.25 s of work after one 2 s pause
  EXPECT_EQ(at(slow, 3.25).pedal, 1.0);
  // Trench: the same motion 2 mm toward the mesial (-x for this frame).
  const PenPath trench = derivedAttemptPath(*pro, Attempt::Trench, up, kAxes, s);
  EXPECT_NEAR(at(trench, 1.0).grip.position.x, 2.0 - s.trench_offset_mm, 1e-9);
  // Over-cut: the whole preparation, then again with every point pushed out from the axis through
  // x = 2: a point 1 mm out (x 3) moves to 2 mm out, one 0.5 mm out moves 0.5 mm further.
  const PenPath over = derivedAttemptPath(*pro, Attempt::Overcut, up, kAxes, s);
  EXPECT_NEAR(at(over, 1.0).grip.position.x, 2.0, 1e-9);
  const double second = 2.0 + 0.3;  // the second pass starts 0.3 s after the first's last sample
  EXPECT_NEAR(at(over, second + 1.5).grip.position.x, 2.0 + 1.0 + s.overcut_offset_mm, 1e-9);
  EXPECT_NEAR(at(over, second + 1.25).grip.position.x, 2.5 + s.overcut_offset_mm * 0.5 / s.overcut_offset_mm, 1e-9);
  // Heavy: the grip three times as far past the bur (1.5 mm), and at least heavy_min_force_n / k.
  const PenPath heavy = derivedAttemptPath(*pro, Attempt::Heavy, up, kAxes, s);
  const double press = std::max(3.0 * 0.5, s.heavy_min_force_n / 1.0);
  EXPECT_NEAR(at(heavy, 1.0).grip.position.z, 0.5 - press, 1e-9);  // the bur at z 0.5, the grip below it
  EXPECT_NEAR(at(heavy, 1.0).grip.position.x, 2.0, 1e-9);
  EXPECT_NEAR(at(heavy, 0.2).grip.position.z, 5.0, 1e-9);  // not cutting: no press, no change
}

TEST(SessionAttempts, TheTiltedBurLeansFifteenDegreesAboutItsTip) {
  DerivedAttemptSettings s;
  auto pro = professionalPath(professional(), "pro", s);
  ASSERT_TRUE(pro.ok());
  const PenPath tilted = derivedAttemptPath(*pro, Attempt::Tilted, {0, 0, 1}, kAxes, s);
  const PenReading r = at(tilted, 1.0);
  const Vec3 axis = r.grip.rotation.rotate({0, 0, 1});
  EXPECT_NEAR(std::acos(axis.z) * 180.0 / std::numbers::pi, s.tilt_deg, 1e-9);
  EXPECT_LT(axis.x, 0.0);  // toward the mesial, -x
  // The tip, kBurGripLocal below the grip, is where the professional's was: (2, 0, -19).
  const Vec3 tip = r.grip.position - r.grip.rotation.rotate(kBurGripLocal);
  EXPECT_NEAR(tip.x, 2.0, 1e-9);
  EXPECT_NEAR(tip.y, 0.0, 1e-9);
  EXPECT_NEAR(tip.z, -kBurGripLocal.z, 1e-9);
}

TEST(SessionAttempts, AClassFivesAxisIsLevelAndTheEditsFollowIt) {
  // The bur along -y (from buccal): across it toward the mesial is still -x, and the trench moves there.
  DerivedAttemptSettings s;
  auto pro = professionalPath(professional(), "pro", s);
  ASSERT_TRUE(pro.ok());
  const PenPath trench = derivedAttemptPath(*pro, Attempt::Trench, {0, -1, 0}, kAxes, s);
  EXPECT_NEAR(at(trench, 1.0).grip.position.x, 2.0 - s.trench_offset_mm, 1e-9);
  // A stopped attempt backs out along the axis (+(-y)), not up.
  const PenPath token = derivedAttemptPath(*pro, Attempt::Token, {0, -1, 0}, kAxes, s);
  EXPECT_NEAR(at(token, endOf(token)).grip.position.y, -s.lift_mm, 1e-9);
}

TEST(SessionAttempts, TheHeavyHandPressesPastTheTasksForceLimit) {
  EXPECT_DOUBLE_EQ(derivedSettingsFor(3.0).heavy_min_force_n, 6.0);
  EXPECT_DOUBLE_EQ(derivedSettingsFor(1.5).heavy_min_force_n, 3.0);
}

}  // namespace
}  // namespace dentsim
