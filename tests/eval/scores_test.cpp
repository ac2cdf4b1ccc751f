// Tests of the score formulas on hand-counted teeth: the empty attempt, the exact ideal, one voxel wrong, every clamp, the report.
#include "eval/scores.h"

#include <gtest/gtest.h>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;

// ---- caries removal ------------------------------------------------------------------------------

// Enamel slab with 8 caries voxels at the top, x 4..7, y 4..5, z 7.
ToothVolume cariousSlab() {
  ToothVolume t = enamelSlab();
  setBox(t, {4, 4, 7}, {8, 6, 8}, makeVoxel(Material::Caries));
  return t;
}

ToothDiff diffOf(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal) {
  auto d = compareTeeth(initial, final_, ideal, 0.2);
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
  // No session steps: elapsed 0 s is before the target, but nothing was removed, so no time points;
  // no contact samples, so no force points.
  const CariesScore s = scoreCariesRemoval(diffOf(t, t, nullptr), SessionStats{}, test::cariesTask());
  EXPECT_EQ(s.removal, 0.0);
  EXPECT_EQ(s.time, 0.0);
  EXPECT_EQ(s.force, 0.0);
  EXPECT_EQ(s.total, 0.0);
}

TEST(CariesScore, HandCountedComponents) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {6, 6, 8}, kEmpty);        // 4 of 8 caries voxels
  setBox(student, {0, 0, 7}, {2, 1, 8}, kEmpty);        // 2 healthy enamel voxels
  // removal 50 x 4/8 = 25; time 25 x (900 - 600)/(900 - 300) = 12.5; force 25 x (10 - 2)/10 = 20.
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), stats(600, 10, 2), test::cariesTask());
  EXPECT_DOUBLE_EQ(s.removal, 25.0);
  EXPECT_DOUBLE_EQ(s.time, 12.5);
  EXPECT_DOUBLE_EQ(s.force, 20.0);
  EXPECT_DOUBLE_EQ(s.total, 57.5);
  EXPECT_DOUBLE_EQ(s.removed_fraction, 0.5);
  EXPECT_NEAR(s.caries_initial_mm3, 0.008, 1e-15);
  EXPECT_NEAR(s.caries_removed_mm3, 0.004, 1e-15);
  EXPECT_NEAR(s.caries_remaining_mm3, 0.004, 1e-15);
  EXPECT_NEAR(s.enamel_removed_mm3, 0.002, 1e-15);
  EXPECT_EQ(s.dentin_removed_mm3, 0.0);
  EXPECT_FALSE(s.pulp_exposed);
}

TEST(CariesScore, PartialFillRemovesProportionally) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  student.voxels.setVoxel(4, 4, 7, makeVoxel(Material::Caries, 20));  // 11 of 8 x 31 units
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), stats(300, 1, 0), test::cariesTask());
  EXPECT_NEAR(s.removal, 50.0 * 11.0 / 248.0, 1e-12);
}

TEST(CariesScore, ClampsHoldAtBothEnds) {
  const ToothVolume t = cariousSlab();
  ToothVolume all_out = t;
  setBox(all_out, {4, 4, 7}, {8, 6, 8}, kEmpty);
  const ToothDiff d = diffOf(t, all_out, nullptr);
  const Task task = test::cariesTask();
  // Before the target: full time points, not more. All caries out: 50.
  const CariesScore fast = scoreCariesRemoval(d, stats(10, 100, 0), task);
  EXPECT_EQ(fast.removal, 50.0);
  EXPECT_EQ(fast.time, 25.0);
  EXPECT_EQ(fast.force, 25.0);
  EXPECT_EQ(fast.total, 100.0);
  // Exactly at the target and the failure time.
  EXPECT_EQ(scoreCariesRemoval(d, stats(300, 1, 0), task).time, 25.0);
  EXPECT_EQ(scoreCariesRemoval(d, stats(900, 1, 0), task).time, 0.0);
  // Beyond failure: 0, not negative. Every contact sample over the force threshold: 0.
  const CariesScore slow = scoreCariesRemoval(d, stats(5000, 100, 100), task);
  EXPECT_EQ(slow.time, 0.0);
  EXPECT_EQ(slow.force, 0.0);
  EXPECT_EQ(slow.total, 50.0);
}

TEST(CariesScore, ToothWithoutCariesGivesNoRemovalPoints) {
  const ToothVolume t = enamelSlab();
  ToothVolume student = t;
  student.voxels.setVoxel(0, 0, 7, kEmpty);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), stats(100, 5, 0), test::cariesTask());
  EXPECT_EQ(s.removal, 0.0);
  EXPECT_EQ(s.time, 0.0);     // no caries removed
  EXPECT_EQ(s.force, 25.0);
}

TEST(CariesScore, PulpExposureIsReported) {
  ToothVolume t = cariousSlab();
  t.voxels.setVoxel(10, 10, 3, makeVoxel(Material::Pulp));
  ToothVolume student = t;
  student.voxels.setVoxel(10, 10, 4, kEmpty);
  const CariesScore s = scoreCariesRemoval(diffOf(t, student, nullptr), stats(100, 5, 0), test::cariesTask());
  EXPECT_TRUE(s.pulp_exposed);
  EXPECT_EQ(s.exposed_pulp_voxels, 1u);
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
  auto s = scoreCavityPreparation(c.diff(), stats(600, 50, 0, 0), test::cavityTask());
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->undercut, 25.0);
  EXPECT_EQ(s->overcut, 25.0);
  EXPECT_EQ(s->parallel, 25.0);
  EXPECT_EQ(s->time, 25.0);
  EXPECT_EQ(s->total, 100.0);
  EXPECT_NEAR(s->ideal_mm3, 0.032, 1e-15);
  EXPECT_NEAR(s->removed_mm3, 0.032, 1e-15);
}

TEST(CavityScore, OneExtraVoxelCostsTheCoefficient) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, kEmpty);  // beside the cavity, kept by the ideal
  for (double coef : {1.0, 2.5}) {
    Task task = test::cavityTask();
    task.cavity.overcut_coefficient = coef;
    auto s = scoreCavityPreparation(c.diff(), stats(600, 50, 0), task);
    ASSERT_TRUE(s.ok());
    EXPECT_NEAR(s->overcut, 25.0 - 1.0 * coef * 100.0 / kIdealVoxels, 1e-12) << coef;
    EXPECT_EQ(s->undercut, 25.0);
    EXPECT_NEAR(s->overcut_percent, 100.0 / kIdealVoxels, 1e-12);
    EXPECT_NEAR(s->overcut_mm3, 0.001, 1e-15);
    EXPECT_NEAR(s->overcut_near_mm3, 0.001, 1e-15);  // 0.1 mm from the cavity, inside the 0.2 mm leeway
    EXPECT_EQ(s->overcut_gross_mm3, 0.0);
  }
}

TEST(CavityScore, PartialVoxelCostsProportionally) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, makeVoxel(Material::Enamel, 21));  // 10 units over
  auto s = scoreCavityPreparation(c.diff(), stats(600, 50, 0), test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->overcut, 25.0 - (10.0 / 31.0) * 100.0 / kIdealVoxels, 1e-12);
}

TEST(CavityScore, OneVoxelLeftCostsTheCoefficient) {
  CavityCase c;
  c.student.voxels.setVoxel(6, 6, 6, makeVoxel(Material::Enamel));  // the ideal removes it
  Task task = test::cavityTask();
  task.cavity.undercut_coefficient = 3.0;
  auto s = scoreCavityPreparation(c.diff(), stats(600, 50, 0), task);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->undercut, 25.0 - 1.0 * 3.0 * 100.0 / kIdealVoxels, 1e-12);
  EXPECT_EQ(s->overcut, 25.0);
}

TEST(CavityScore, ClampsHoldAtBothEnds) {
  CavityCase c;
  setBox(c.student, {0, 0, 0}, {16, 16, 8}, kEmpty);  // everything: 2016 voxels over-cut
  const Task task = test::cavityTask();
  auto wrecked = scoreCavityPreparation(c.diff(), stats(100000, 50, 0, 100000), task);
  ASSERT_TRUE(wrecked.ok());
  EXPECT_EQ(wrecked->overcut, 0.0);
  EXPECT_EQ(wrecked->undercut, 25.0);
  EXPECT_EQ(wrecked->parallel, 0.0);
  EXPECT_EQ(wrecked->time, 0.0);
  EXPECT_EQ(wrecked->total, 25.0);

  const CavityCase exact;
  // Before the target: 25, not more. One minute over at 5 per minute: 20. 100 samples tilted: 24.
  auto fast = scoreCavityPreparation(exact.diff(), stats(1, 50, 0, 0), task);
  ASSERT_TRUE(fast.ok());
  EXPECT_EQ(fast->time, 25.0);
  auto late = scoreCavityPreparation(exact.diff(), stats(660, 50, 0, 100), task);
  ASSERT_TRUE(late.ok());
  EXPECT_DOUBLE_EQ(late->time, 20.0);
  EXPECT_DOUBLE_EQ(late->parallel, 24.0);
  EXPECT_DOUBLE_EQ(late->total, 25.0 + 25.0 + 24.0 + 20.0);
}

TEST(CavityScore, DoingNothingScoresZero) {
  CavityCase c;
  c.student = c.initial;
  auto s = scoreCavityPreparation(c.diff(), SessionStats{}, test::cavityTask());
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s->nothing_removed);
  EXPECT_EQ(s->total, 0.0);
  EXPECT_NEAR(s->undercut_percent, 100.0, 1e-12);
}

TEST(CavityScore, EmptyOrMissingIdealIsAnError) {
  const ToothVolume t = enamelSlab();
  auto none = scoreCavityPreparation(diffOf(t, t, nullptr), SessionStats{}, test::cavityTask());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("needs the ideal"), std::string::npos) << none.message();
  auto empty = scoreCavityPreparation(diffOf(t, t, &t), SessionStats{}, test::cavityTask());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.message().find("ideal cavity is empty"), std::string::npos) << empty.message();
}

// ---- report --------------------------------------------------------------------------------------

TEST(ScoreReport, CavityReportShowsComponentsAndInputs) {
  CavityCase c;
  c.student.voxels.setVoxel(10, 6, 7, kEmpty);
  const ToothDiff d = c.diff();
  const Task task = test::cavityTask();
  const SessionStats st = stats(660, 50, 3, 100);
  auto s = scoreCavityPreparation(d, st, task);
  ASSERT_TRUE(s.ok());
  const nlohmann::ordered_json j = scoreReportJson(task, {"t.json", "a.dvol", "b.dvol", "c.dvol", ""}, d, st, *s);
  EXPECT_EQ(j["format"], "dentsim-score");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["task"]["kind"], "cavity");
  EXPECT_EQ(j["inputs"]["final"], "b.dvol");
  EXPECT_TRUE(j["inputs"]["session"].is_null());
  EXPECT_EQ(j["total"].get<double>(), s->total);
  EXPECT_EQ(j["components"]["overcut"]["points"].get<double>(), s->overcut);
  EXPECT_EQ(j["components"]["parallel"]["parallel_over"], 100);
  EXPECT_EQ(j["volumes"]["enamel"]["units"]["overcut"], 31);
  EXPECT_EQ(j["volumes"]["all"]["units"]["ideal_cavity"], 32 * 31);
  EXPECT_EQ(j["session"]["contact_samples"], 50);
}

TEST(ScoreReport, CariesReportShowsComponents) {
  const ToothVolume t = cariousSlab();
  ToothVolume student = t;
  setBox(student, {4, 4, 7}, {6, 6, 8}, kEmpty);
  const ToothDiff d = diffOf(t, student, nullptr);
  const SessionStats st = stats(600, 10, 2);
  const CariesScore s = scoreCariesRemoval(d, st, test::cariesTask());
  const nlohmann::ordered_json j = scoreReportJson(test::cariesTask(), {}, d, st, s);
  EXPECT_EQ(j["task"]["kind"], "caries");
  EXPECT_EQ(j["components"]["removal"]["points"].get<double>(), 25.0);
  EXPECT_EQ(j["components"]["force"]["force_over"], 2);
  EXPECT_EQ(j["total"].get<double>(), 57.5);
  EXPECT_FALSE(j["volumes"]["caries"].contains("overcut_mm3"));  // no ideal, no over-cut
}

}  // namespace
}  // namespace dentsim
