// The haptic step's budget: a partial contact pass carried over and finished next step, cut jobs that wait and catch up, replay that follows the recorded schedule, a bounded change of force, and the swept check against a thin wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "io/pen_playback.h"
#include "sim/contact.h"
#include "sim/haptic_loop.h"
#include "sim_fixtures.h"
#include "volume/brick_volume.h"

namespace dentsim {
namespace {

using test::Block;
using test::flatBlock;
using test::sphereBur;

constexpr double kR = 0.5;  // bur radius [mm]

bool sameContacts(std::span<const ContactPoint> a, std::span<const ContactPoint> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].point != b[i].point || !(a[i].position == b[i].position) || a[i].depth_mm != b[i].depth_mm ||
        !(a[i].normal == b[i].normal))
      return false;
  return true;
}

// The sphere bur 0.05 mm into dentin (the tool frame's origin is the tip), with the whole pass's contacts.
struct PressedBur {
  Block b = flatBlock(Material::Dentin);
  ToolModel bur = sphereBur(kR, 0.03);
  VoxelField field{b.volume, b.frame};
  Pose pose{{0.8, 0.8, b.surface_mm - 0.05}, Quat{}};
  ContactFinder whole{bur.shell.size()}, budgeted{bur.shell.size()};
  std::vector<ContactPoint> expected = [this] {
    auto c = whole.find(field, bur.shell, pose);
    return std::vector<ContactPoint>(c.begin(), c.end());
  }();
};

TEST(ContactBudget, APassThatReachesEveryClusterGivesTheUnbudgetedContacts) {
  PressedBur p;
  auto& [b, bur, field, pose, whole, budgeted, expected] = p;
  ContactStats bs;
  ASSERT_GT(expected.size(), 50u);
  ContactBudget roomy;
  roomy.max_points = 1u << 30;
  const auto got = budgeted.find(field, bur.shell, pose, &bs, &roomy);
  EXPECT_TRUE(sameContacts(got, expected));
  EXPECT_EQ(bs.clusters_left, 0u);
  EXPECT_EQ(bs.points_left, 0u);
  EXPECT_EQ(bs.clusters_reached, uint32_t(bur.shell.clusters.size()));
  // Ordered by point, as the cutter's turns expect.
  EXPECT_TRUE(std::is_sorted(got.begin(), got.end(), [](const ContactPoint& x, const ContactPoint& y) { return x.point < y.point; }));
}

TEST(ContactBudget, ThePointsAPassDidNotReachComeFirstInTheNextAndTheTwoMakeTheWhole) {
  PressedBur p;
  auto& [b, bur, field, pose, whole, budgeted, expected] = p;

  // Half the sampled points' worth of budget: the pass stops early, and what it did not reach has no
  // contacts yet (there was no earlier pass to carry them from).
  ContactStats first;
  ContactBudget half;
  half.max_points = 300;
  const auto partial = budgeted.find(field, bur.shell, pose, &first, &half);
  ASSERT_GT(first.clusters_left, 0u);
  EXPECT_GT(first.points_left, 0u);
  EXPECT_EQ(first.contacts_carried, 0u);
  EXPECT_LT(partial.size(), expected.size());
  EXPECT_EQ(first.clusters_reached + first.clusters_left, uint32_t(bur.shell.clusters.size()));

  // The next pass, at the same pose, reaching exactly as many clusters as the first left: those are
  // the ones it reaches, and the clusters the first pass did reach keep its contacts. Together: the
  // whole pass, point for point.
  ContactStats second;
  ContactBudget rest;
  rest.clusters = first.clusters_left;
  const auto joined = budgeted.find(field, bur.shell, pose, &second, &rest);
  EXPECT_EQ(second.clusters_reached, first.clusters_left);
  EXPECT_EQ(second.contacts_carried, uint32_t(partial.size()));
  EXPECT_TRUE(sameContacts(joined, expected));
}

// ---- the loop ------------------------------------------------------------------------------------------

struct BudgetRun {
  BrickVolume final_volume{3};
  std::vector<SessionSchedule> schedules;
  std::vector<Vec3> forces;
  double removed_mm3 = 0.0;
  uint64_t overruns = 0, late_steps = 0, max_lag = 0, forced = 0;
  uint64_t cuts_run = 0;      // cut jobs run, the flush's included
  uint64_t cutting_steps = 0; // steps with the pedal down (each queues or runs one job)
  double expected_mm3 = 0.0;  // what the jobs run should have removed: demand x the hardness they met
  uint32_t flushed = 0;  // jobs still waiting after the last step
};

// Runs the press-and-slide cut for `steps` steps with the given budget; with `follow`, each step
// follows the schedule recorded at its index instead.
BudgetRun runBudgeted(StepBudget budget, uint32_t points, const SimParams& params, int steps,
                      const std::vector<SessionSchedule>* follow = nullptr, double pedal = 1.0) {
  Block b = flatBlock(Material::Dentin);
  const ToolModel bur = sphereBur(kR, 0.03, {0, 0, kR});
  const PenPath path = test::pressAndSlide(b, kR, 0.3, 3.0, pedal, steps / params.device.rate_hz);
  SimParams with_bur = params;
  with_bur.burs["test_sphere"].cutting_ability = 0.8;
  ScriptedPen pen(path, PenRole::Drill);
  HapticLoop loop(b.volume, b.frame, with_bur, bur, nullptr, nullptr);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, Pose{{0.4, 0.8, b.surface_mm + kR}, Quat{}});
  loop.setBudget(budget, points);
  // With the clock's budget every step first waits 20 us, past the budget's 2 us, so that what the
  // budget cuts short does not depend on how fast this machine is.
  if (budget == StepBudget::Clock)
    loop.setStepHook([](uint64_t, void*) { std::this_thread::sleep_for(std::chrono::microseconds(20)); }, nullptr);
  BudgetRun run;
  for (int s = 0; s < steps; ++s) {
    if (follow != nullptr) loop.followSchedule(&(*follow)[size_t(s)]);
    const StepReport& r = loop.step();
    run.schedules.push_back(r.schedule);
    run.forces.push_back(r.tools[0].display.force);
    run.late_steps += r.cuts_waiting > 0 ? 1 : 0;
    run.max_lag = std::max(run.max_lag, r.cut_lag_steps);
    run.forced += r.cuts_forced;
    run.cuts_run += r.cuts_run;
    run.cutting_steps += r.speed > 0 ? 1 : 0;
    run.expected_mm3 += r.cut.expected_mm3;
  }
  run.flushed = loop.flushCuts();  // as stop() and a replay's last step do
  run.cuts_run += run.flushed;
  run.expected_mm3 += run.flushed > 0 ? loop.lastReport().cut.expected_mm3 : 0.0;
  run.removed_mm3 = loop.latest().removed_mm3;
  run.overruns = loop.latest().contact_overruns;
  run.final_volume = b.volume;
  return run;
}

TEST(StepBudget, AClockBudgetTooSmallForTheWorkStillCutsAllItWasAskedToAndReplaysToTheSameVoxels) {
  // A budget of 2 us that each step starts past (runBudgeted stalls it 20 us): every contact pass that
  // must sample tests one such cluster and stops, and every cut waits for a later step. Replay
  // follows the schedules the steps report, and must give the same voxels.
  SimParams tight = defaultSimParams();
  tight.device.contact_budget = 0.001;
  tight.device.cut_budget = 0.001;
  const int steps = 400;
  const BudgetRun live = runBudgeted(StepBudget::Clock, 0, tight, steps);
  EXPECT_GT(live.overruns, uint64_t(steps / 2)) << "the budget never cut a pass short";
  const size_t short_steps = size_t(std::count_if(live.schedules.begin(), live.schedules.end(),
                                                  [](const SessionSchedule& s) { return !s.isDefault(); }));
  EXPECT_GT(short_steps, size_t(steps / 2));
  // Jobs that waited kMaxCutLagSteps ran over budget, so none waited longer; the rest ran when the
  // run ended.
  EXPECT_GT(live.forced, 0u);
  EXPECT_EQ(live.max_lag, HapticLoop::kMaxCutLagSteps - 1);
  EXPECT_GT(live.flushed, 0u);
  EXPECT_GT(live.removed_mm3, 0.0);
  const BudgetRun replay = runBudgeted(StepBudget::None, 0, tight, steps, &live.schedules);
  EXPECT_TRUE(replay.final_volume == live.final_volume) << "replay left other voxels than the budgeted run";
  EXPECT_EQ(replay.removed_mm3, live.removed_mm3);
  EXPECT_EQ(replay.forces, live.forces);
  EXPECT_EQ(replay.flushed, live.flushed);
  // The unbudgeted run of the same pen never waits.
  const BudgetRun whole = runBudgeted(StepBudget::None, 0, defaultSimParams(), steps);
  EXPECT_EQ(whole.overruns, 0u);
  EXPECT_EQ(whole.late_steps, 0u);
  EXPECT_EQ(whole.flushed, 0u);
}

TEST(StepBudget, CutsLeftForLaterAllRunOnceInStepOrderAndCatchUp) {
  // A schedule in which, of every ten steps, four run no cut and the fifth runs all that waited (a
  // cutting stage up to 4 ms late, half the time): the queue keeps the jobs in step order, each runs
  // once, and none is left when the run ends.
  const int steps = 400;
  std::vector<SessionSchedule> schedule(static_cast<size_t>(steps));
  for (int s = 0; s < steps; ++s)
    if (s % 10 < 4) schedule[size_t(s)].cuts = 0;
  const BudgetRun held = runBudgeted(StepBudget::None, 0, defaultSimParams(), steps, &schedule);
  const BudgetRun whole = runBudgeted(StepBudget::None, 0, defaultSimParams(), steps);
  EXPECT_EQ(held.max_lag, 3u);
  EXPECT_EQ(held.late_steps, uint64_t(steps / 10 * 4));
  EXPECT_EQ(held.flushed, 0u);
  EXPECT_EQ(held.cuts_run, held.cutting_steps);
  EXPECT_EQ(whole.cuts_run, whole.cutting_steps);
  // The demand the jobs carried met the same tissue (expected removal within 3 %). What five jobs
  // run in one step can take is the tissue within reach of the head where it was (the cutter takes
  // voxels within reach_mm of each contact's way out), so in this extreme schedule the removal
  // itself falls about 8 % short of the every-step run's; the bench measures the real budget's.
  ASSERT_GT(whole.removed_mm3, 0.0);
  EXPECT_NEAR(held.expected_mm3, whole.expected_mm3, 0.03 * whole.expected_mm3);
  EXPECT_NEAR(held.removed_mm3, whole.removed_mm3, 0.10 * whole.removed_mm3);
  EXPECT_FALSE(held.final_volume == whole.final_volume);  // the order of events did change
}

TEST(StepBudget, APointBudgetKeepsTheForceWithinAFewPerCentOfTheWholePass) {
  // The bur pressed 0.3 mm into dentin and slid along it at 3 mm/s, pedal up (so that the two runs
  // meet the same tissue), with 64 points sampled a step, a pass cut short nearly every step: the
  // force shown stays close to the unbudgeted step's, because points not reached keep their last
  // contact, carried across its tangent plane to where the point is now.
  const int steps = 300;
  const BudgetRun whole = runBudgeted(StepBudget::None, 0, defaultSimParams(), steps, nullptr, 0.0);
  const BudgetRun part = runBudgeted(StepBudget::Points, 64, defaultSimParams(), steps, nullptr, 0.0);
  EXPECT_GT(part.overruns, uint64_t(steps / 4));
  double sq = 0, mean = 0;
  for (size_t i = 50; i < size_t(steps); ++i) {  // past the first touch
    sq += std::pow(norm(part.forces[i] - whole.forces[i]), 2);
    mean += norm(whole.forces[i]);
  }
  const double n = double(steps - 50);
  const double rms = std::sqrt(sq / n);
  mean /= n;
  ASSERT_GT(mean, 0.1);
  EXPECT_LT(rms, 0.05 * mean) << "RMS " << rms << " N against a mean force of " << mean << " N";
}

TEST(StepBudget, TheForceShownChangesByAtMostItsLimitAStep) {
  // The pen jumps 0.3 mm into the block in one step: the coupling force jumps, the force shown
  // climbs to it at max_force_change_n_per_ms and no faster, then agrees with it.
  Block b = flatBlock(Material::Enamel);
  const ToolModel bur = sphereBur(kR, 0.03, {0, 0, kR});
  PenPath path;
  for (double t : {0.0, 0.0099, 0.01, 1.0}) {
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Drill;
    s.pose = Pose{{0.8, 0.8, b.surface_mm + kR + (t < 0.01 ? 0.2 : -2.5)}, Quat{}};
    path.samples.push_back(s);
  }
  SimParams params = defaultSimParams();
  params.device.max_force_change_n_per_ms = 0.5;
  ScriptedPen pen(path, PenRole::Drill);
  HapticLoop loop(b.volume, b.frame, params, bur, nullptr, nullptr);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, Pose{{0.8, 0.8, b.surface_mm + kR + 0.2}, Quat{}});
  Vec3 last;
  int limited = 0;
  for (int s = 0; s < 60; ++s) {
    const StepReport& r = loop.step();
    const Vec3 f = r.tools[0].display.force;
    EXPECT_LE(norm(f - last), 0.5 + 1e-12) << "step " << s;
    limited += r.force_limited[0] ? 1 : 0;
    last = f;
  }
  EXPECT_GE(limited, 4) << "the jump never met the limit";
  // The coupling force (2.5 mm behind the proxy at 1 N/mm) reached, within the device's clamp.
  EXPECT_NEAR(last.z, loop.latest().tools[0].display.force.z, 1e-12);
  EXPECT_GT(last.z, 2.0);
}

// ---- the swept check -----------------------------------------------------------------------------------

// A 0.3 mm enamel wall, level-10 voxels (0.0125 mm), between z = 0.6 and 0.9 mm; empty above and below.
Block thinWall() {
  Block b = flatBlock(Material::Enamel, 72);  // tissue up to 0.9 mm
  for (uint32_t z = 0; z < 48; ++z)           // nothing below 0.6 mm
    for (uint32_t y = 0; y < 128; ++y)
      for (uint32_t x = 0; x < 128; ++x) b.volume.setVoxel(x, y, z, makeVoxel(Material::Empty));
  b.surface_mm = 0.9;
  return b;
}

struct WallRun {
  double lowest_tip_mm = 1e9;  // the lowest the bur's tip went [mm]
  double final_tip_mm = 0.0;   // where it rests at the end [mm]
  uint32_t swept_steps = 0;    // steps the swept check cut short
};

// The pen drives the bur's tip from 0.25 mm above the wall's top straight down at speed_mm_s, to
// 2.5 mm below the top (1.9 mm past the wall's far face), and holds there: a student pushing hard
// (2.5 N through the coupling) after a fast stab.
WallRun driveThroughWall(double speed_mm_s, double max_proxy_speed, double pedal, StepBudget budget = StepBudget::None,
                         uint32_t points = 0) {
  Block b = thinWall();
  const ToolModel bur = sphereBur(kR, 0.03, {0, 0, kR});
  SimParams params = defaultSimParams();
  params.coupling.max_proxy_speed_mm_per_s = max_proxy_speed;
  const double start = b.surface_mm + 0.25 + kR;  // the grip (sphere centre)
  PenPath path;
  const double travel = 0.25 + 2.5;
  for (double t : {0.0, travel / speed_mm_s, 0.2}) {
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Drill;
    s.pose = Pose{{0.8, 0.8, start - std::min(speed_mm_s * t, travel)}, Quat{}};
    s.pedal = pedal;
    path.samples.push_back(s);
  }
  ScriptedPen pen(path, PenRole::Drill);
  HapticLoop loop(b.volume, b.frame, params, bur, nullptr, nullptr);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, Pose{{0.8, 0.8, start}, Quat{}});
  loop.setBudget(budget, points);
  WallRun run;
  for (int s = 0; s < 200; ++s) {
    const StepReport& r = loop.step();
    run.lowest_tip_mm = std::min(run.lowest_tip_mm, loop.proxy(PenRole::Drill)->toolPose().position.z);
    run.swept_steps += r.tools[0].sweep_taken < r.tools[0].sweep_poses ? 1 : 0;
  }
  run.final_tip_mm = loop.proxy(PenRole::Drill)->toolPose().position.z;
  return run;
}

// The wall's top is at 0.9 mm and its far face at 0.6 mm. Stopped: the tip never came within 0.2 mm
// of the far face, and it rests on the top, held by the wall's springs.
void expectStopped(const WallRun& run) {
  EXPECT_GT(run.lowest_tip_mm, 0.6 + 0.2) << "the tip went most of the way through a 0.3 mm wall";
  EXPECT_NEAR(run.final_tip_mm, 0.9, 0.05) << "the tip does not rest on the wall";
}

TEST(SweptCheck, ABurAt200MmPerSecondIsStoppedByAThinEnamelWall) {
  // 200 mm/s, the proxy's own speed limit: 0.2 mm a step, two thirds of the wall.
  for (double pedal : {0.0, 1.0}) {
    SCOPED_TRACE(pedal > 0 ? "cutting" : "not cutting");
    const WallRun run = driveThroughWall(200.0, 200.0, pedal);
    expectStopped(run);
    EXPECT_GT(run.swept_steps, 0u) << "the swept check never met the wall";
  }
}

TEST(SweptCheck, AProxyFastEnoughToJumpTheWallInOneStepIsStoppedToo) {
  // 2 m/s with the proxy's speed limit raised to match: 2 mm a step, seven times the wall. Without
  // the swept check the first step would put the tip 1.5 mm below the wall's far face, with nothing
  // there to push it back.
  const WallRun run = driveThroughWall(2000.0, 2000.0, 0.0);
  expectStopped(run);
  EXPECT_GT(run.swept_steps, 0u);
  // And with a budget that lets each step sample only 200 points.
  expectStopped(driveThroughWall(2000.0, 2000.0, 0.0, StepBudget::Points, 200));
}

}  // namespace
}  // namespace dentsim
