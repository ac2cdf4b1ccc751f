// Tests of compareTeeth: fill amounts per tissue counted by hand, the set formulas for full fills, leeway split, pulp exposure, frame checks.
#include "eval/tooth_diff.h"

#include <gtest/gtest.h>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;
constexpr uint64_t kFull = DS_FILL_FULL;  // fill units of one whole voxel

Result<ToothDiff> compare(const ToothVolume& i, const ToothVolume& f, const ToothVolume* k, double leeway_mm = 0.2) {
  return compareTeeth(i, f, k, leeway_mm);
}

// ---- amounts -------------------------------------------------------------------------------------

TEST(ToothDiff, IdenticalVolumesRemoveNothing) {
  const ToothVolume slab = enamelSlab();
  auto d = compare(slab, slab, &slab);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts& e = d->tissue(Material::Enamel);
  EXPECT_EQ(e.initial, 2048 * kFull);  // 16 x 16 x 8 voxels
  EXPECT_EQ(e.remaining, 2048 * kFull);
  EXPECT_EQ(e.removed, 0u);
  EXPECT_EQ(e.ideal_cavity, 0u);
  EXPECT_EQ(e.undercut, 0u);
  EXPECT_EQ(e.overcut, 0u);
  EXPECT_EQ(d->tissue(Material::Dentin), TissueAmounts{});
  EXPECT_FALSE(d->pulp_exposed);
}

TEST(ToothDiff, CuttingExactlyTheIdealLeavesNoUnderOrOverCut) {
  const ToothVolume initial = enamelSlab();
  ToothVolume ideal = initial;
  setBox(ideal, {6, 6, 6}, {10, 10, 8}, kEmpty);  // 4 x 4 x 2 = 32 voxels, across four bricks
  auto d = compare(initial, ideal, &ideal);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts e = d->total();
  EXPECT_EQ(e.ideal_cavity, 32 * kFull);
  EXPECT_EQ(e.removed, 32 * kFull);
  EXPECT_EQ(e.remaining, (2048 - 32) * kFull);
  EXPECT_EQ(e.undercut, 0u);
  EXPECT_EQ(e.overcut, 0u);
}

TEST(ToothDiff, FullFillsGiveTheSetFormulas) {
  // Ideal cavity C: x 2..5 (4 x 4 x 2 = 32 voxels). The student cuts x 4..7 (32 voxels): the
  // overlap x 4..5 (16 voxels) is right, C AND R = x 2..3 (16) is under-cut, and
  // I AND NOT R AND NOT C = x 6..7 (16) is over-cut.
  const ToothVolume initial = enamelSlab();
  ToothVolume ideal = initial, student = initial;
  setBox(ideal, {2, 2, 6}, {6, 6, 8}, kEmpty);
  setBox(student, {4, 2, 6}, {8, 6, 8}, kEmpty);
  auto d = compare(initial, student, &ideal);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts e = d->total();
  EXPECT_EQ(e.ideal_cavity, 32 * kFull);
  EXPECT_EQ(e.removed, 32 * kFull);
  EXPECT_EQ(e.undercut, 16 * kFull);
  EXPECT_EQ(e.overcut, 16 * kFull);
  EXPECT_EQ(e.overcut_near + e.overcut_gross, e.overcut);
}

TEST(ToothDiff, PartialFillsCountInFillUnits) {
  ToothVolume initial = test::emptyTooth(), ideal = test::emptyTooth(), student = test::emptyTooth();
  // Voxel A: initial 31, ideal keeps 10, student keeps 20 -> c = 21, under-cut 10.
  // Voxel B: initial 31, ideal keeps 10, student keeps 5  -> c = 21, over-cut 5.
  // Voxel C: initial 20 (a cut surface), ideal 31 (more than there was: clipped to 20), student 0
  //          -> c = 0, over-cut 20.
  initial.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Dentin));
  initial.voxels.setVoxel(2, 1, 1, makeVoxel(Material::Dentin));
  initial.voxels.setVoxel(9, 9, 9, makeVoxel(Material::Dentin, 20));
  ideal.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Dentin, 10));
  ideal.voxels.setVoxel(2, 1, 1, makeVoxel(Material::Dentin, 10));
  ideal.voxels.setVoxel(9, 9, 9, makeVoxel(Material::Dentin, 31));
  student.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Dentin, 20));
  student.voxels.setVoxel(2, 1, 1, makeVoxel(Material::Dentin, 5));
  auto d = compare(initial, student, &ideal);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts& t = d->tissue(Material::Dentin);
  EXPECT_EQ(t.initial, 31u + 31u + 20u);
  EXPECT_EQ(t.remaining, 20u + 5u);
  EXPECT_EQ(t.removed, 11u + 26u + 20u);
  EXPECT_EQ(t.ideal_cavity, 21u + 21u);
  EXPECT_EQ(t.undercut, 10u);
  EXPECT_EQ(t.overcut, 5u + 20u);
  // removed = ideal cavity - under-cut + over-cut, voxel by voxel and so in the sums.
  EXPECT_EQ(t.removed, t.ideal_cavity - t.undercut + t.overcut);
}

TEST(ToothDiff, VolumesPerTissueInMm3) {
  ToothVolume initial = test::emptyTooth();
  setBox(initial, {0, 0, 0}, {4, 4, 4}, makeVoxel(Material::Dentin));   // 64 voxels
  setBox(initial, {0, 0, 4}, {4, 4, 6}, makeVoxel(Material::Enamel));   // 32 voxels
  setBox(initial, {1, 1, 1}, {2, 2, 2}, makeVoxel(Material::Pulp));     // 1 voxel (was dentin)
  setBox(initial, {2, 2, 5}, {3, 3, 6}, makeVoxel(Material::Caries));   // 1 voxel (was enamel)
  ToothVolume student = initial;
  setBox(student, {0, 0, 5}, {4, 4, 6}, kEmpty);                        // 15 enamel + the caries voxel
  student.voxels.setVoxel(0, 0, 3, makeVoxel(Material::Dentin, 16));   // 15 units of dentin
  auto d = compare(initial, student, nullptr);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_FALSE(d->has_ideal);
  EXPECT_EQ(d->tissue(Material::Enamel).initial, 31 * kFull);
  EXPECT_EQ(d->tissue(Material::Dentin).initial, 63 * kFull);
  EXPECT_EQ(d->tissue(Material::Pulp).initial, 1 * kFull);
  EXPECT_EQ(d->tissue(Material::Caries).initial, 1 * kFull);
  EXPECT_EQ(d->tissue(Material::Enamel).removed, 15 * kFull);
  EXPECT_EQ(d->tissue(Material::Caries).removed, 1 * kFull);
  EXPECT_EQ(d->tissue(Material::Dentin).removed, 15u);
  // 0.1 mm voxels: 0.001 mm^3 each, 0.001/31 mm^3 per fill unit.
  EXPECT_NEAR(d->mm3(d->tissue(Material::Enamel).removed), 0.015, 1e-15);
  EXPECT_NEAR(d->mm3(d->tissue(Material::Dentin).removed), 15 * test::kUnitMm3, 1e-15);
  EXPECT_NEAR(d->mm3(d->tissue(Material::Dentin).initial), 0.063, 1e-15);
  // Without an ideal there is no cavity to compare with.
  EXPECT_EQ(d->total().ideal_cavity, 0u);
  EXPECT_EQ(d->total().overcut, 0u);
}

TEST(ToothDiff, UniformBricksCountLikeDenseOnes) {
  // Level 5: whole bricks set as tiles take the analytic path; the totals must equal the volume's own.
  ToothVolume initial = test::emptyTooth(5);
  for (uint32_t bx = 0; bx < 4; ++bx)
    for (uint32_t by = 0; by < 4; ++by) initial.voxels.setBrickUniform({bx, by, 0}, makeVoxel(Material::Dentin));
  initial.voxels.setBrickUniform({1, 1, 1}, makeVoxel(Material::Enamel, 7));
  initial.voxels.setVoxel(3, 3, 3, makeVoxel(Material::Pulp));
  ToothVolume student = initial;
  student.voxels.setVoxel(20, 20, 2, kEmpty);  // one dentin voxel in a tile brick
  auto d = compare(initial, student, &initial);
  ASSERT_TRUE(d.ok()) << d.message();
  const MaterialTotals totals = initial.voxels.materialTotals();
  for (Material m : kScoredTissues) EXPECT_EQ(d->tissue(m).initial, totals.fill_sum[size_t(m)]) << materialName(m);
  EXPECT_EQ(d->tissue(Material::Dentin).removed, kFull);
  EXPECT_EQ(d->tissue(Material::Dentin).overcut, kFull);  // the ideal (the initial) kept it
  EXPECT_EQ(d->tissue(Material::Dentin).overcut_gross, kFull);
}

// ---- leeway --------------------------------------------------------------------------------------

TEST(ToothDiff, LeewaySplitsNearFromGross) {
  // The ideal removes one voxel, (7,4,7). The student leaves it and cuts (8,4,7), one voxel away
  // across a brick face (near: 0.1 mm <= 0.2 mm), (9,5,7) at sqrt(5) voxels (0.224 mm: gross),
  // (7,4,5) at exactly 2 voxels (0.2 mm: near, the leeway is inclusive) and (7,14,7) ten voxels
  // away (gross).
  const ToothVolume initial = enamelSlab();
  ToothVolume ideal = initial, student = initial;
  ideal.voxels.setVoxel(7, 4, 7, kEmpty);
  for (auto [x, y, z] : {std::array<uint32_t, 3>{8, 4, 7}, {9, 5, 7}, {7, 4, 5}, {7, 14, 7}})
    student.voxels.setVoxel(x, y, z, kEmpty);
  auto d = compare(initial, student, &ideal, 0.2);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts e = d->total();
  EXPECT_EQ(e.undercut, kFull);
  EXPECT_EQ(e.overcut, 4 * kFull);
  EXPECT_EQ(e.overcut_near, 2 * kFull);
  EXPECT_EQ(e.overcut_gross, 2 * kFull);
  // With no leeway every over-cut voxel beside the cavity is gross.
  auto tight = compare(initial, student, &ideal, 0.0);
  ASSERT_TRUE(tight.ok());
  EXPECT_EQ(tight->total().overcut_near, 0u);
  EXPECT_EQ(tight->total().overcut_gross, 4 * kFull);
}

TEST(ToothDiff, PartlyCutIdealVoxelIsItsOwnNeighbour) {
  // One voxel that the ideal cuts to 10 and the student to 5: ideal cavity and over-cut at once,
  // at distance 0 from the cavity, so near even with no leeway.
  ToothVolume initial = enamelSlab(), ideal = initial, student = initial;
  ideal.voxels.setVoxel(3, 3, 7, makeVoxel(Material::Enamel, 10));
  student.voxels.setVoxel(3, 3, 7, makeVoxel(Material::Enamel, 5));
  auto d = compare(initial, student, &ideal, 0.0);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->total().overcut, 5u);
  EXPECT_EQ(d->total().overcut_near, 5u);
}

// ---- pulp exposure -------------------------------------------------------------------------------

// Dentin block z 0..8 with one pulp voxel at (8,4,3), just across the brick face x = 8 from (7,4,3).
ToothVolume toothWithPulp() {
  ToothVolume t = test::emptyTooth();
  setBox(t, {0, 0, 0}, {16, 16, 8}, makeVoxel(Material::Dentin));
  t.voxels.setVoxel(8, 4, 3, makeVoxel(Material::Pulp));
  return t;
}

TEST(ToothDiff, UntouchedPulpIsNotExposed) {
  const ToothVolume t = toothWithPulp();
  ToothVolume student = t;
  setBox(student, {0, 0, 6}, {16, 16, 8}, kEmpty);  // cuts far above the pulp
  auto d = compare(t, student, nullptr);
  ASSERT_TRUE(d.ok());
  EXPECT_FALSE(d->pulp_exposed);
  EXPECT_EQ(d->exposed_pulp_voxels, 0u);
}

TEST(ToothDiff, PulpThatLostFillIsExposed) {
  const ToothVolume t = toothWithPulp();
  ToothVolume student = t;
  student.voxels.setVoxel(8, 4, 3, makeVoxel(Material::Pulp, 30));
  auto d = compare(t, student, nullptr);
  ASSERT_TRUE(d.ok());
  EXPECT_TRUE(d->pulp_exposed);
  EXPECT_EQ(d->exposed_pulp_voxels, 1u);
  EXPECT_EQ(d->tissue(Material::Pulp).removed, 1u);
}

TEST(ToothDiff, PulpBesideACutOutVoxelIsExposed) {
  const ToothVolume t = toothWithPulp();
  // Cutting the dentin beside it across the brick face to empty opens the pulp; from two sides it
  // is still one exposed voxel.
  ToothVolume student = t;
  student.voxels.setVoxel(7, 4, 3, kEmpty);
  student.voxels.setVoxel(8, 4, 4, kEmpty);
  auto d = compare(t, student, nullptr);
  ASSERT_TRUE(d.ok());
  EXPECT_TRUE(d->pulp_exposed);
  EXPECT_EQ(d->exposed_pulp_voxels, 1u);
  EXPECT_EQ(d->tissue(Material::Pulp).removed, 0u);

  // Thinning the dentin without cutting it through, or cutting a diagonal neighbour, leaves it closed.
  ToothVolume thin = t;
  thin.voxels.setVoxel(7, 4, 3, makeVoxel(Material::Dentin, 1));
  thin.voxels.setVoxel(7, 5, 3, kEmpty);
  auto closed = compare(t, thin, nullptr);
  ASSERT_TRUE(closed.ok());
  EXPECT_FALSE(closed->pulp_exposed);
}

// ---- frames --------------------------------------------------------------------------------------

TEST(ToothDiff, MismatchedLevelOrFrameIsAnErrorNamingTheFile) {
  const ToothVolume t = enamelSlab();
  const DiffNames names{"start.dvol", "student.dvol", "prof.dvol"};

  const ToothVolume bigger = test::emptyTooth(5);
  auto level = compareTeeth(t, bigger, nullptr, 0.2, names);
  ASSERT_FALSE(level.ok());
  EXPECT_EQ(level.message(), "student.dvol: octree level 5 differs from start.dvol's 4; score volumes of one level");

  ToothVolume finer = t;
  finer.frame.voxel_mm = 0.05;
  auto size = compareTeeth(t, t, &finer, 0.2, names);
  ASSERT_FALSE(size.ok());
  EXPECT_EQ(size.message(), "prof.dvol: voxel size 0.05 mm differs from start.dvol's 0.1 mm");

  ToothVolume moved = t;
  moved.frame.origin_mm[1] = 1.5;
  auto origin = compareTeeth(t, moved, nullptr, 0.2, names);
  ASSERT_FALSE(origin.ok());
  EXPECT_EQ(origin.message(), "student.dvol: origin y 1.5 mm differs from start.dvol's 0 mm");

  // Default names are the roles.
  auto roles = compareTeeth(t, moved, nullptr, 0.2);
  ASSERT_FALSE(roles.ok());
  EXPECT_EQ(roles.message().rfind("final: origin y", 0), 0u) << roles.message();
}

}  // namespace
}  // namespace dentsim
