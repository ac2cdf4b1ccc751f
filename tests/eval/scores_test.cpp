// Tests of the score formulas on hand-counted teeth: the empty attempt, the exact ideal, one voxel wrong, healthy tissue outside the zone, the pulp's cap, parts not scored, every clamp, warnings, the report.
#include "eval/scores.h"

#include <gtest/gtest.h>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;

// ---- caries removal ------------------------------------------------------------------------------

// Enamel slab with 8 caries voxels at the top, x 4..7, y 4..5, z 7: the target is these 8 voxels
// (the space above them holds no tissue).
ToothVolume cariousSlab() {
  ToothVolume t = enamelSlab();
  setBox(t, {4, 4, 7}, {8, 6, 8}, makeVoxel(Material::Caries));
  return t;
}

ToothDiff diffOf(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal) {
  auto d = compareTeeth(initial, final_, ideal, ZoneOptions{});
  EXPECT_TRUE(d.ok()) << d.message();
  return d.ok() ? *d : ToothDiff{};
}

SessionStats stats(double elapsed_s, uint64_t contact, uint64_t force_over, uint64_t parallel_over = 0) {
  SessionStats s;
  s.rate_hz = 1000;
  s.elapsed_s = elapsed_s;
  s.contact_samples = contact;
  s.force_over = force_over;
  s.parallel_over = parallel_over;
  return s;
}

TEST(CariesScore, DoingNothingScoresZero) {
  const ToothVolume t = cariousSlab();
  // An empty session: elapsed 0 s is before the target, but nothing was removed, so no time points;
  // no contact samples, so no force points.
  const SessionStats empty;
  const CariesScore s = scoreCariesRemoval(diffOf(t, t, nullptr), &empty, test::cariesTask());
  EXPECT_EQ(s.removal, 0.0);
  EXPECT_EQ(s.time, 0.0);
  EXPECT_EQ(s.force, 0.0);
  EXPECT_EQ(s.total, 0.0);
  EXPECT_EQ(s.total_max, 100.0);
}

TEST(CariesScore, HandCountedComponents) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {6, 6, 8}, kEmpty);        // 4 of 8 caries voxels
  setBox(student, {0, 0, 7}, {2, 1, 8}, kEmpty);        // 2 healthy enamel voxels, 4 voxels from the caries
  // removal 50 x 4/8 = 25; time 25 x (900 - 600)/(900 - 300) = 12.5; force 25 x (10 - 2)/10 = 20:
  // Table 4's 57.5. The 2 enamel voxels are 25% of the caries' volume, at 0.5 points per percent 12.5.
  // Half the caries removed earns half the time and force parts: 25 + 0.5 x (12.5 + 20) - 12.5 = 28.75.
  const SessionStats st = stats(600, 10, 2);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_DOUBLE_EQ(s.removal, 25.0);
  EXPECT_DOUBLE_EQ(*s.time, 12.5);
  EXPECT_DOUBLE_EQ(*s.force, 20.0);
  EXPECT_DOUBLE_EQ(s.earned_time, 6.25);
  EXPECT_DOUBLE_EQ(s.earned_force, 10.0);
  EXPECT_DOUBLE_EQ(s.paper_total, 57.5);
  EXPECT_DOUBLE_EQ(s.healthy_outside_percent, 25.0);
  EXPECT_DOUBLE_EQ(s.healthy_deduction, 12.5);
  EXPECT_DOUBLE_EQ(s.total, 28.75);
  EXPECT_DOUBLE_EQ(s.removed_fraction, 0.5);
  EXPECT_NEAR(s.caries_initial_mm3, 0.008, 1e-15);
  EXPECT_NEAR(s.caries_removed_mm3, 0.004, 1e-15);
  EXPECT_NEAR(s.caries_remaining_mm3, 0.004, 1e-15);
  EXPECT_NEAR(s.removedMm3(Material::Enamel), 0.002, 1e-15);
  EXPECT_NEAR(s.healthy_outside_mm3, 0.002, 1e-15);
  EXPECT_EQ(s.removedMm3(Material::Dentin), 0.0);
  EXPECT_FALSE(s.pulp_exposed);
}

TEST(CariesScore, HealthyCostScalesWithTheCoefficient) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {8, 6, 8}, kEmpty);   // all the caries
  student.voxels.setVoxel(12, 12, 7, kEmpty);      // one voxel far away: 12.5% of the caries
  const SessionStats st = stats(10, 100, 0);
  for (double coef : {0.0, 0.5, 2.0, 100.0}) {
    Task task = test::cariesTask();
    task.caries.healthy_coefficient = coef;
    const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, task);
    EXPECT_DOUBLE_EQ(s.paper_total, 100.0);
    EXPECT_DOUBLE_EQ(s.healthy_deduction, 12.5 * coef) << coef;
    EXPECT_DOUBLE_EQ(s.total, std::max(0.0, 100.0 - 12.5 * coef)) << coef;  // never below 0
  }
}

TEST(CariesScore, HealthyTissueInsideTheLeewayIsFree) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {8, 6, 8}, kEmpty);
  student.voxels.setVoxel(3, 4, 7, kEmpty);   // 0.1 mm from the caries
  student.voxels.setVoxel(8, 6, 7, kEmpty);   // sqrt(2) voxels: 0.14 mm
  student.voxels.setVoxel(4, 4, 5, kEmpty);   // 0.2 mm below: the bound is inclusive
  const SessionStats st = stats(10, 100, 0);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_EQ(s.healthy_deduction, 0.0);
  EXPECT_NEAR(s.removedMm3(Material::Enamel), 0.003, 1e-15);
  EXPECT_EQ(s.total, 100.0);
  student.voxels.setVoxel(1, 4, 7, kEmpty);   // 0.3 mm: outside
  const CariesScore out = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_DOUBLE_EQ(out.healthy_deduction, 0.5 * 12.5);
}

TEST(CariesScore, PartialFillRemovesProportionally) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  student.voxels.setVoxel(4, 4, 7, makeVoxel(Material::Caries, 20));  // 11 of 8 x 31 units
  const SessionStats st = stats(300, 1, 0);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_NEAR(s.removal, 50.0 * 11.0 / 248.0, 1e-12);
}

TEST(CariesScore, ClampsHoldAtBothEnds) {
  const ToothVolume t = cariousSlab();
  ToothVolume all_out = t;
  setBox(all_out, {4, 4, 7}, {8, 6, 8}, kEmpty);
  const ToothDiff d = diffOf(t, all_out, nullptr);
  const Task task = test::cariesTask();
  // Before the target: full time points, not more. All caries out: 50.
  const SessionStats quick = stats(10, 100, 0);
  const CariesScore fast = scoreCariesRemoval(d, &quick, task);
  EXPECT_EQ(fast.removal, 50.0);
  EXPECT_EQ(fast.time, 25.0);
  EXPECT_EQ(fast.force, 25.0);
  EXPECT_EQ(fast.total, 100.0);
  // Exactly at the target and the failure time.
  const SessionStats at_target = stats(300, 1, 0), at_failure = stats(900, 1, 0);
  EXPECT_EQ(scoreCariesRemoval(d, &at_target, task).time, 25.0);
  EXPECT_EQ(scoreCariesRemoval(d, &at_failure, task).time, 0.0);
  // Beyond failure: 0, not negative. Every contact sample over the force threshold: 0.
  const SessionStats late = stats(5000, 100, 100);
  const CariesScore slow = scoreCariesRemoval(d, &late, task);
  EXPECT_EQ(slow.time, 0.0);
  EXPECT_EQ(slow.force, 0.0);
  EXPECT_EQ(slow.total, 50.0);
}

TEST(CariesScore, WithoutASessionTimeAndForceAreNotScored) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {8, 6, 8}, kEmpty);
  student.voxels.setVoxel(12, 12, 7, kEmpty);  // 12.5% of the caries outside the zone
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), nullptr, test::cariesTask());
  EXPECT_FALSE(s.time.has_value());
  EXPECT_FALSE(s.force.has_value());
  EXPECT_EQ(s.removal, 50.0);
  EXPECT_EQ(s.paper_total, 50.0);
  EXPECT_EQ(s.total_max, 50.0);  // out of the parts scored, not 100
  EXPECT_DOUBLE_EQ(s.total, 50.0 - 6.25);
}

TEST(CariesScore, ToothWithoutCariesGivesNoRemovalPoints) {
  const ToothVolume t = enamelSlab();
  ToothVolume student = t;
  const SessionStats st = stats(100, 5, 0);
  const CariesScore untouched = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_EQ(untouched.removal, 0.0);
  EXPECT_EQ(untouched.time, 0.0);     // no caries removed
  EXPECT_EQ(untouched.force, 25.0);  // Table 4's part, earned at the share removed: none
  EXPECT_EQ(untouched.earned_force, 0.0);
  EXPECT_EQ(untouched.total, 0.0);
  // Any healthy cut on a tooth without caries has nothing to scale by: it costs everything.
  student.voxels.setVoxel(0, 0, 7, kEmpty);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, test::cariesTask());
  EXPECT_EQ(s.healthy_deduction, 100.0);
  EXPECT_EQ(s.total, 0.0);
}

TEST(CariesScore, PulpExposureCapsTheTotal) {
  ToothVolume t = cariousSlab();
  t.voxels.setVoxel(10, 10, 3, makeVoxel(Material::Pulp));
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {8, 6, 8}, kEmpty);
  student.voxels.setVoxel(10, 10, 3, makeVoxel(Material::Pulp, 30));  // the pulp loses one unit
  const SessionStats st = stats(100, 5, 0);
  Task task = test::cariesTask();
  task.caries.healthy_coefficient = 0.0;  // the cap alone
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), &st, task);
  EXPECT_TRUE(s.pulp_exposed);
  EXPECT_EQ(s.exposed_pulp_voxels, 1u);
  EXPECT_EQ(s.paper_total, 100.0);
  EXPECT_TRUE(s.pulp_cap_applied);
  EXPECT_EQ(s.total, 50.0);
  task.pulp_exposure_cap = 20.0;
  EXPECT_EQ(scoreCariesRemoval(diffOf(t, student, nullptr), &st, task).total, 20.0);
  // Without a session the cap is a share of what can be scored: 20 of 100 is 10 of 50.
  EXPECT_EQ(scoreCariesRemoval(diffOf(t, student, nullptr), nullptr, task).total, 10.0);
}

// ---- cavity preparation --------------------------------------------------------------------------

// The ideal removes x 6..9, y 6..9, z 6..7 from the enamel slab: 32 voxels.
struct CavityCase {
  ToothVolume initial = enamelSlab();
  ToothVolume ideal;
  ToothVolume student;
  CavityCase() {
    ideal = initial;
    setBox(ideal, {6, 6, 6}, {10, 10, 8}, kEmpty);
    student = ideal;
  }
  ToothDiff diff() const { return diffOf(initial, student, &ideal); }
};
constexpr double kIdealVoxels = 32.0;

TEST(CavityScore, ExactIdealScoresFullCutting) {
  const CavityCase c;
  const SessionStats st = stats(600, 50, 0, 0);
  auto s = scoreCavityPreparation(c.diff(), &st, test::cavityTask());
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->undercut, 25.0);
  EXPECT_EQ(s->overcut, 25.0);
  EXPECT_EQ(s->parallel, 25.0);
  EXPECT_EQ(s->time, 25.0);
  EXPECT_EQ(s->force_deduction, 0.0);
  EXPECT_EQ(s->total, 100.0);
  EXPECT_NEAR(s->ideal_mm3, 0.032, 1e-15);
  EXPECT_NEAR(s->removed_mm3, 0.032, 1e-15);
}

TEST(CavityScore, OneExtraVoxelCostsTheCoefficient) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, kEmpty);  // beside the cavity, kept by the ideal
  const SessionStats st = stats(600, 50, 0);
  for (double coef : {1.0, 2.5}) {
    Task task = test::cavityTask();
    task.cavity.overcut_coefficient = coef;
    task.cavity.near_overcut_weight = 1.0;  // the voxel is in the leeway: counted in full here
    auto s = scoreCavityPreparation(c.diff(), &st, task);
    ASSERT_TRUE(s.ok());
    EXPECT_NEAR(s->overcut, 25.0 - 1.0 * coef * 100.0 / kIdealVoxels, 1e-12) << coef;
    EXPECT_EQ(s->undercut, 25.0);
    EXPECT_NEAR(s->overcut_percent, 100.0 / kIdealVoxels, 1e-12);
    EXPECT_NEAR(s->overcut_mm3, 0.001, 1e-15);
    EXPECT_NEAR(s->overcut_near_mm3, 0.001, 1e-15);  // 0.1 mm from the cavity, inside the 0.2 mm leeway
    EXPECT_EQ(s->overcut_gross_mm3, 0.0);
  }
}

TEST(CavityScore, OverCutInTheLeewayCountsAtItsWeight) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, kEmpty);  // 0.1 mm beside the cavity: in the 0.2 mm leeway
  const SessionStats st = stats(600, 50, 0);
  for (double weight : {0.0, 0.5}) {
    Task task = test::cavityTask();
    task.cavity.near_overcut_weight = weight;
    auto s = scoreCavityPreparation(c.diff(), &st, task);
    ASSERT_TRUE(s.ok());
    EXPECT_NEAR(s->overcut, 25.0 - weight * 100.0 / kIdealVoxels, 1e-12) << weight;
    EXPECT_NEAR(s->overcut_counted_mm3, weight * 0.001, 1e-15) << weight;
    // Table 5 itself counts the voxel in full, whatever the weight.
    EXPECT_NEAR(s->paper_total, 100.0 - 100.0 / kIdealVoxels, 1e-12) << weight;
  }
}

TEST(CavityScore, PartialVoxelCostsProportionally) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, makeVoxel(Material::Enamel, 21));  // 10 units over
  const SessionStats st = stats(600, 50, 0);
  Task task = test::cavityTask();
  task.cavity.near_overcut_weight = 1.0;
  auto s = scoreCavityPreparation(c.diff(), &st, task);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->overcut, 25.0 - (10.0 / 31.0) * 100.0 / kIdealVoxels, 1e-12);
}

TEST(CavityScore, OneVoxelLeftCostsTheCoefficient) {
  CavityCase c;
  c.student.voxels.setVoxel(6, 6, 6, makeVoxel(Material::Enamel));  // the ideal removes it
  Task task = test::cavityTask();
  task.cavity.undercut_coefficient = 3.0;
  const SessionStats st = stats(600, 50, 0);
  auto s = scoreCavityPreparation(c.diff(), &st, task);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->undercut, 25.0 - 1.0 * 3.0 * 100.0 / kIdealVoxels, 1e-12);
  EXPECT_EQ(s->overcut, 25.0);
}

TEST(CavityScore, ClampsHoldAtBothEnds) {
  CavityCase c;
  setBox(c.student, {0, 0, 0}, {16, 16, 8}, kEmpty);  // everything: 2016 voxels over-cut
  const Task task = test::cavityTask();
  const SessionStats worst = stats(100000, 50, 0, 100000);
  auto wrecked = scoreCavityPreparation(c.diff(), &worst, task);
  ASSERT_TRUE(wrecked.ok());
  EXPECT_EQ(wrecked->overcut, 0.0);
  EXPECT_EQ(wrecked->undercut, 25.0);
  EXPECT_EQ(wrecked->parallel, 0.0);
  EXPECT_EQ(wrecked->time, 0.0);
  EXPECT_EQ(wrecked->total, 25.0);

  const CavityCase exact;
  // Before the target: 25, not more. One minute over at 5 per minute: 20. 100 samples tilted: 24.
  const SessionStats quick = stats(1, 50, 0, 0), late_tilted = stats(660, 50, 0, 100);
  auto fast = scoreCavityPreparation(exact.diff(), &quick, task);
  ASSERT_TRUE(fast.ok());
  EXPECT_EQ(fast->time, 25.0);
  auto late = scoreCavityPreparation(exact.diff(), &late_tilted, task);
  ASSERT_TRUE(late.ok());
  EXPECT_DOUBLE_EQ(*late->time, 20.0);
  EXPECT_DOUBLE_EQ(*late->parallel, 24.0);
  EXPECT_DOUBLE_EQ(late->total, 25.0 + 25.0 + 24.0 + 20.0);
}

TEST(CavityScore, ForceErrorsCostTheCoefficientPerPercent) {
  const CavityCase c;
  // 30 of 120 contact samples over the limit: 25%, at 0.5 points per percent 12.5.
  const SessionStats st = stats(600, 120, 30);
  auto s = scoreCavityPreparation(c.diff(), &st, test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(*s->force_deduction, 12.5);
  EXPECT_DOUBLE_EQ(s->paper_total, 100.0);
  EXPECT_DOUBLE_EQ(s->total, 87.5);
}

TEST(CavityScore, DoingNothingScoresZero) {
  CavityCase c;
  c.student = c.initial;
  const SessionStats empty;
  auto s = scoreCavityPreparation(c.diff(), &empty, test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s->nothing_removed);
  EXPECT_TRUE(s->ideal_missed);
  EXPECT_EQ(s->total, 0.0);
  EXPECT_NEAR(s->undercut_percent, 100.0, 1e-12);
}

TEST(CavityScore, ACutThatMissesTheIdealScoresZero) {
  // A quick, upright cut of 8 voxels far from the ideal: Table 5 keeps its time and parallel parts
  // (50) and the under-cut's 0; none of the ideal was cut, so none of them is earned.
  CavityCase c;
  c.student = c.initial;
  setBox(c.student, {0, 12, 6}, {4, 14, 7}, kEmpty);
  const SessionStats st = stats(60, 50, 0, 0);
  auto s = scoreCavityPreparation(c.diff(), &st, test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_FALSE(s->nothing_removed);
  EXPECT_TRUE(s->ideal_missed);
  EXPECT_EQ(s->completion, 0.0);
  EXPECT_EQ(s->parallel, 25.0);
  EXPECT_EQ(s->time, 25.0);
  EXPECT_EQ(s->earned_parallel, 0.0);
  EXPECT_EQ(s->earned_time, 0.0);
  EXPECT_EQ(s->paper_total, 50.0);
  EXPECT_EQ(s->total, 0.0);
  EXPECT_NEAR(s->overcut_gross_mm3, 0.008, 1e-15);
}

TEST(CavityScore, WithoutASessionParallelTimeAndForceAreNotScored) {
  CavityCase c;
  c.student.voxels.setVoxel(6, 6, 6, makeVoxel(Material::Enamel));  // one voxel left: 25 - 3.125
  auto s = scoreCavityPreparation(c.diff(), nullptr, test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_FALSE(s->parallel.has_value());
  EXPECT_FALSE(s->time.has_value());
  EXPECT_FALSE(s->force_deduction.has_value());
  EXPECT_EQ(s->total_max, 50.0);
  // 31 of the 32 voxels cut: the under-cut part loses 100/32, and the over-cut part is earned at 31/32.
  EXPECT_DOUBLE_EQ(s->completion, 31.0 / 32.0);
  EXPECT_DOUBLE_EQ(s->total, 25.0 - 100.0 / kIdealVoxels + 25.0 * 31.0 / 32.0);
}

TEST(CavityScore, EmptyOrMissingIdealIsAnError) {
  const ToothVolume t = enamelSlab();
  const SessionStats empty;
  auto none = scoreCavityPreparation(diffOf(t, t, nullptr), &empty, test::cavityTask());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("needs the ideal"), std::string::npos) << none.message();
  auto nothing = scoreCavityPreparation(diffOf(t, t, &t), &empty, test::cavityTask());
  ASSERT_FALSE(nothing.ok());
  EXPECT_NE(nothing.message().find("ideal cavity is empty"), std::string::npos) << nothing.message();
}

// ---- warnings ------------------------------------------------------------------------------------

// Enamel over dentin, so that the crown is found facing +z.
ToothVolume layeredSlab() {
  ToothVolume t = test::emptyTooth();
  setBox(t, {0, 0, 0}, {16, 16, 6}, makeVoxel(Material::Dentin));
  setBox(t, {0, 0, 6}, {16, 16, 8}, makeVoxel(Material::Enamel));
  return t;
}

// ---- access cavity ----------------------------------------------------------------------------------

// The enamel slab over a pulp chamber x 6..9, y 6..9, z 2..3 (32 voxels); the ideal access removes
// the 64 enamel voxels above it, x 6..9, y 6..9, z 4..7, so the chamber's top faces open space.
struct AccessCase {
  ToothVolume initial = enamelSlab();
  ToothVolume ideal, student;
  AccessCase() {
    setBox(initial, {6, 6, 2}, {10, 10, 4}, makeVoxel(Material::Pulp));
    ideal = initial;
    setBox(ideal, {6, 6, 4}, {10, 10, 8}, kEmpty);
    student = ideal;
  }
  ToothDiff diff() const { return diffOf(initial, student, &ideal); }
};

Task accessTask() {
  Task t = test::cavityTask();
  t.kind = TaskKind::Access;
  return t;
}

TEST(AccessScore, AnOpenedChamberIsTheExerciseNotAFault) {
  const AccessCase c;
  const SessionStats st = stats(600, 50, 0, 0);
  const ToothDiff d = c.diff();
  ASSERT_TRUE(d.pulp_exposed);  // the pulp's top faces voxels that held enamel and are now empty
  auto access = scoreCavityPreparation(d, &st, accessTask());
  ASSERT_TRUE(access.ok()) << access.message();
  EXPECT_TRUE(access->access);
  EXPECT_FALSE(access->pulp_cap_applied);
  EXPECT_FALSE(access->unopened_cap_applied);
  EXPECT_EQ(access->total, 100.0);
  // The same cut as a cavity preparation exposes the pulp and is capped at 50.
  auto cavity = scoreCavityPreparation(d, &st, test::cavityTask());
  ASSERT_TRUE(cavity.ok());
  EXPECT_TRUE(cavity->pulp_cap_applied);
  EXPECT_EQ(cavity->total, 50.0);
}

TEST(AccessScore, AChamberLeftClosedCapsTheTotal) {
  AccessCase c;
  setBox(c.student, {6, 6, 4}, {10, 10, 5}, makeVoxel(Material::Enamel));  // the last layer of the roof left: 16 voxels
  const SessionStats st = stats(600, 50, 0, 0);
  const ToothDiff d = c.diff();
  ASSERT_FALSE(d.pulp_exposed);
  Task task = accessTask();
  auto s = scoreCavityPreparation(d, &st, task);
  ASSERT_TRUE(s.ok()) << s.message();
  // Under-cut 16 of 64 voxels, 25 %: 25 - 25 = 0 points; over-cut, parallel and time full (Table 5's
  // 75), earned at the 48 of 64 voxels cut: 56.25, capped at 40.
  EXPECT_EQ(s->undercut, 0.0);
  EXPECT_EQ(s->paper_total, 75.0);
  EXPECT_TRUE(s->unopened_cap_applied);
  EXPECT_EQ(s->total, 40.0);
  task.access.unopened_cap = 30.0;
  EXPECT_EQ(scoreCavityPreparation(d, &st, task)->total, 30.0);
  // Without a session the cap is a share of what can be scored: 30 of 100 is 15 of 50.
  EXPECT_EQ(scoreCavityPreparation(d, nullptr, task)->total, 15.0);
  // A cap above the score takes nothing.
  task.access.unopened_cap = 90.0;
  auto high = scoreCavityPreparation(d, &st, task);
  EXPECT_FALSE(high->unopened_cap_applied);
  EXPECT_EQ(high->total, 56.25);
  // As a cavity preparation the same cut is not capped: the pulp is not exposed.
  EXPECT_EQ(scoreCavityPreparation(d, &st, test::cavityTask())->total, 56.25);
}

TEST(AccessScore, TheReportAndTheLineSayWhetherTheChamberWasOpened) {
  AccessCase c;
  setBox(c.student, {6, 6, 4}, {10, 10, 5}, makeVoxel(Material::Enamel));
  const SessionStats st = stats(600, 50, 0, 0);
  const ToothDiff d = c.diff();
  const Task task = accessTask();
  auto s = scoreCavityPreparation(d, &st, task);
  ASSERT_TRUE(s.ok());
  const nlohmann::ordered_json r = scoreReportJson(task, ScoreInputs{}, d, &st, *s);
  EXPECT_EQ(r["task"]["kind"], "access");
  EXPECT_FALSE(r["deductions"].contains("pulp_exposure"));
  EXPECT_EQ(r["deductions"]["pulp_unopened"]["pulp_opened"], false);
  EXPECT_EQ(r["deductions"]["pulp_unopened"]["applied"], true);
  EXPECT_EQ(r["deductions"]["pulp_unopened"]["cap"], 40.0);
  EXPECT_EQ(r["deductions"]["pulp_unopened"]["cap_of_100"], 40.0);
  const std::string line = scoreSummary(*s, ScoreInputs{});
  EXPECT_EQ(line.rfind("access cavity score 40.00 / 100", 0), 0u) << line;
  EXPECT_NE(line.find("capped: pulp chamber not opened"), std::string::npos) << line;
  EXPECT_NE(line.find("pulp chamber not opened"), std::string::npos) << line;
}

TEST(ScoreWarnings, AGoodExerciseHasNone) {
  const ToothVolume t = layeredSlab();
  ToothVolume ideal = t;
  setBox(ideal, {6, 6, 6}, {10, 10, 8}, kEmpty);
  EXPECT_TRUE(scoreWarnings(test::cavityTask(), diffOf(t, ideal, &ideal), "t.dvol").empty());
}

TEST(ScoreWarnings, AxisAwayFromTheCrownIdealOnTheRootsAndACutElsewhere) {
  const ToothVolume t = layeredSlab();
  ToothVolume ideal = t, student = t;
  setBox(ideal, {6, 6, 0}, {10, 10, 2}, kEmpty);      // at the bottom: the roots' side
  setBox(student, {0, 0, 7}, {2, 2, 8}, kEmpty);      // nowhere near it
  Task task = test::cavityTask();
  task.insertion_axis = {0, 0, -1};
  const std::vector<std::string> w = scoreWarnings(task, diffOf(t, student, &ideal), "t.dvol");
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("task test_cavity on t.dvol: the insertion axis (0.00, 0.00, -1.00) points away from the crown"),
            std::string::npos) << w[0];
  EXPECT_NE(w[1].find("the ideal cavity lies mostly outside the crown half"), std::string::npos) << w[1];
  EXPECT_NE(w[1].find("100%"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("does not overlap the ideal cavity at all"), std::string::npos) << w[2];
}

// ---- report --------------------------------------------------------------------------------------

TEST(ScoreReport, CavityReportShowsComponentsAndInputs) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, kEmpty);
  const ToothDiff d = c.diff();
  const Task task = test::cavityTask();
  const SessionStats st = stats(660, 50, 3, 100);
  auto s = scoreCavityPreparation(d, &st, task);
  ASSERT_TRUE(s.ok());
  ScoreInputs in;
  in.task = "t.json";
  in.initial = "a.dvol";
  in.final_ = "b.dvol";
  in.ideal = idealVolumeFile("c.dvol");
  in.ideal_from = "command line";
  const nlohmann::ordered_json j = scoreReportJson(task, in, d, &st, *s);
  EXPECT_EQ(j["format"], "dentsim-score");
  EXPECT_EQ(j["version"], 2);
  EXPECT_EQ(j["task"]["kind"], "cavity");
  EXPECT_EQ(j["inputs"]["final"], "b.dvol");
  EXPECT_EQ(j["inputs"]["ideal"]["path"], "c.dvol");
  EXPECT_EQ(j["inputs"]["ideal"]["kind"], "volume");
  EXPECT_EQ(j["inputs"]["ideal"]["from"], "command line");
  EXPECT_TRUE(j["inputs"]["session"].is_null());
  EXPECT_EQ(j["total"].get<double>(), s->total);
  EXPECT_EQ(j["total_max"].get<double>(), 100.0);
  EXPECT_TRUE(j["not_scored"].empty());
  EXPECT_EQ(j["components"]["overcut"]["points"].get<double>(), s->overcut);
  EXPECT_EQ(j["components"]["parallel"]["parallel_over"], 100);
  EXPECT_EQ(j["deductions"]["force"]["force_over"], 3);
  EXPECT_EQ(j["volumes"]["enamel"]["units"]["container_removed"] .get<uint64_t>() +
                j["volumes"]["enamel"]["units"]["leeway_removed"].get<uint64_t>(), 31u);
  EXPECT_EQ(j["volumes"]["all"]["units"]["target"], 32 * 31);
  EXPECT_EQ(j["zones"]["target"], "ideal cavity");
  EXPECT_DOUBLE_EQ(j["zones"]["target_removed_percent"].get<double>(), 100.0);
  EXPECT_EQ(j["session"]["contact_samples"], 50);
}

TEST(ScoreReport, MissingSessionIsNullWithTheReason) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {6, 6, 8}, kEmpty);
  const ToothDiff d = diffOf(t, student, nullptr);
  const CariesScore s = scoreCariesRemoval(d, nullptr, test::cariesTask());
  ScoreInputs in;
  const nlohmann::ordered_json j = scoreReportJson(test::cariesTask(), in, d, nullptr, s);
  EXPECT_EQ(j["total_max"].get<double>(), 50.0);
  EXPECT_TRUE(j["components"]["time"]["points"].is_null());
  EXPECT_EQ(j["components"]["time"]["not_scored"], "no session was given");
  EXPECT_TRUE(j["components"]["force"]["points"].is_null());
  ASSERT_EQ(j["not_scored"].size(), 2u);
  EXPECT_EQ(j["not_scored"][0]["part"], "time");
  EXPECT_EQ(j["not_scored"][1]["part"], "force");
  EXPECT_EQ(j["session"]["missing"], "no session was given");
  EXPECT_TRUE(j["inputs"]["ideal"].is_null());
  const std::string line = scoreSummary(s, in);
  EXPECT_NE(line.find("/ 50"), std::string::npos) << line;
  EXPECT_NE(line.find("time and force not scored: no session was given"), std::string::npos) << line;
}

TEST(ScoreReport, CariesReportShowsComponentsDeductionsAndZones) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {6, 6, 8}, kEmpty);
  setBox(student, {0, 0, 7}, {2, 1, 8}, kEmpty);
  const ToothDiff d = diffOf(t, student, nullptr);
  const SessionStats st = stats(600, 10, 2);
  const CariesScore s = scoreCariesRemoval(d, &st, test::cariesTask());
  const nlohmann::ordered_json j = scoreReportJson(test::cariesTask(), {}, d, &st, s);
  EXPECT_EQ(j["task"]["kind"], "caries");
  EXPECT_EQ(j["components"]["removal"]["points"].get<double>(), 25.0);
  EXPECT_EQ(j["components"]["force"]["force_over"], 2);
  EXPECT_EQ(j["paper_total"].get<double>(), 57.5);
  EXPECT_EQ(j["deductions"]["healthy"]["points"].get<double>(), 12.5);
  // Time and force: the table's parts, and the half of them that half the caries removed earns.
  EXPECT_EQ(j["components"]["time"]["table_points"].get<double>(), 12.5);
  EXPECT_EQ(j["components"]["time"]["points"].get<double>(), 6.25);
  EXPECT_EQ(j["components"]["force"]["earned_share"].get<double>(), 0.5);
  EXPECT_EQ(j["completion"]["share"].get<double>(), 0.5);
  EXPECT_EQ(j["total"].get<double>(), 28.75);
  EXPECT_EQ(j["zones"]["target"], "caries and its access along the insertion axis");
  EXPECT_DOUBLE_EQ(j["zones"]["target_removed_percent"].get<double>(), 50.0);
  EXPECT_NEAR(j["zones"]["healthy_outside_zone_mm3"].get<double>(), 0.002, 1e-15);
  EXPECT_FALSE(j["volumes"]["caries"].contains("overcut_mm3"));  // no ideal, no over-cut
}

// The healthy tissues the report and the line list are the tissue table's, in its order: a tissue
// added to the table is reported without another list to edit.
TEST(ScoreReport, HealthyRemovedListsEveryHealthyTissueOfTheTable) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {0, 0, 7}, {2, 1, 8}, kEmpty);  // two enamel voxels, outside the zone
  const ToothDiff d = diffOf(t, student, nullptr);
  const CariesScore s = scoreCariesRemoval(d, nullptr, test::cariesTask());
  const nlohmann::ordered_json j = scoreReportJson(test::cariesTask(), {}, d, nullptr, s);
  std::vector<std::string> expected, reported;
  for (const TissueRow& row : kTissueTable)
    if (isHealthyTissue(row.material)) expected.push_back(row.name);
  for (const auto& [name, mm3] : j["healthy_removed_mm3"].items()) reported.push_back(name);
  EXPECT_EQ(reported, expected);
  EXPECT_EQ(expected, (std::vector<std::string>{"enamel", "dentin", "pulp"}));  // caries is the lesion
  EXPECT_GT(j["healthy_removed_mm3"]["enamel"].get<double>(), 0.0);
  EXPECT_EQ(j["healthy_removed_mm3"]["dentin"].get<double>(), 0.0);
  const std::string line = scoreSummary(s, ScoreInputs{});
  // "... mm^3 removed (enamel 0.002, dentin 0.000, pulp 0.000), ...": each healthy tissue, in order.
  size_t at = line.find("mm^3 removed (");
  ASSERT_NE(at, std::string::npos) << line;
  for (const std::string& name : expected) {
    at = line.find(name + " ", at);
    ASSERT_NE(at, std::string::npos) << name << " missing from: " << line;
  }
}

}  // namespace
}  // namespace dentsim
