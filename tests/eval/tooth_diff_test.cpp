// Tests of compareTeeth: fill amounts per tissue counted by hand, the set formulas for full fills, the zones (the caries' access, the leeway), pulp exposure, frame checks.
#include "eval/tooth_diff.h"

#include <gtest/gtest.h>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;
constexpr uint64_t kFull = DS_FILL_FULL;  // fill units of one whole voxel

Result<ToothDiff> compare(const ToothVolume& i, const ToothVolume& f, const ToothVolume* k, double leeway_mm = 0.2,
                          Vec3 axis = {0, 0, 1}) {
  return compareTeeth(i, f, k, ZoneOptions{leeway_mm, axis});
}

// Every tissue's initial fill lies in exactly one zone, and so does what was removed from it.
void expectZonesPartition(const ToothDiff& d) {
  for (Material m : kScoredTissues) {
    const TissueAmounts& a = d.tissue(m);
    EXPECT_EQ(a.target + a.leeway + a.container, a.initial) << materialName(m);
    EXPECT_EQ(a.target_removed + a.leeway_removed + a.container_removed, a.removed) << materialName(m);
  }
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
  EXPECT_EQ(e.target, 0u);
  EXPECT_EQ(e.undercut(), 0u);
  EXPECT_EQ(e.overcut(), 0u);
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
  EXPECT_EQ(e.target, 32 * kFull);
  EXPECT_EQ(e.removed, 32 * kFull);
  EXPECT_EQ(e.remaining, (2048 - 32) * kFull);
  EXPECT_EQ(e.undercut(), 0u);
  EXPECT_EQ(e.overcut(), 0u);
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
  EXPECT_EQ(e.target, 32 * kFull);
  EXPECT_EQ(e.removed, 32 * kFull);
  EXPECT_EQ(e.undercut(), 16 * kFull);
  EXPECT_EQ(e.overcut(), 16 * kFull);
  EXPECT_EQ(e.leeway_removed + e.container_removed, e.overcut());
  expectZonesPartition(*d);
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
  EXPECT_EQ(t.target, 21u + 21u);
  EXPECT_EQ(t.undercut(), 10u);
  EXPECT_EQ(t.overcut(), 5u + 20u);
  // removed = ideal cavity - under-cut + over-cut, voxel by voxel and so in the sums.
  EXPECT_EQ(t.removed, t.target - t.undercut() + t.overcut());
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
  // Without an ideal the target is the caries and what lies above it: here the caries voxel alone
  // (the enamel ends at z = 6). What was cut beyond it is the enamel and the dentin.
  EXPECT_EQ(d->total().target, 1 * kFull);
  EXPECT_EQ(d->total().target_removed, 1 * kFull);
  EXPECT_EQ(d->total().overcut(), 15 * kFull + 15u);
  expectZonesPartition(*d);
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
  EXPECT_EQ(d->tissue(Material::Dentin).overcut(), kFull);  // the ideal (the initial) kept it
  EXPECT_EQ(d->tissue(Material::Dentin).container_removed, kFull);
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
  EXPECT_EQ(e.undercut(), kFull);
  EXPECT_EQ(e.overcut(), 4 * kFull);
  EXPECT_EQ(e.leeway_removed, 2 * kFull);
  EXPECT_EQ(e.container_removed, 2 * kFull);
  // With no leeway every over-cut voxel beside the cavity is gross.
  auto tight = compare(initial, student, &ideal, 0.0);
  ASSERT_TRUE(tight.ok());
  EXPECT_EQ(tight->total().leeway_removed, 0u);
  EXPECT_EQ(tight->total().container_removed, 4 * kFull);
}

TEST(ToothDiff, PartlyCutIdealVoxelIsItsOwnNeighbour) {
  // One voxel that the ideal cuts to 10 and the student to 5: ideal cavity and over-cut at once,
  // at distance 0 from the cavity, so near even with no leeway.
  ToothVolume initial = enamelSlab(), ideal = initial, student = initial;
  ideal.voxels.setVoxel(3, 3, 7, makeVoxel(Material::Enamel, 10));
  student.voxels.setVoxel(3, 3, 7, makeVoxel(Material::Enamel, 5));
  auto d = compare(initial, student, &ideal, 0.0);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->total().overcut(), 5u);
  EXPECT_EQ(d->total().leeway_removed, 5u);
}

// ---- the caries' zone ------------------------------------------------------------------------------

TEST(ToothDiff, CariesTargetIsTheLesionAndTheTissueAboveIt) {
  // Caries x 4..7, y 4..5, z 3..4 (16 voxels) under the enamel's top at z = 8: the target holds
  // the caries and the enamel over it, z 5..7 (24 voxels). Cutting exactly that is all in target.
  ToothVolume initial = enamelSlab();
  setBox(initial, {4, 4, 3}, {8, 6, 5}, makeVoxel(Material::Caries));
  ToothVolume student = initial;
  setBox(student, {4, 4, 3}, {8, 6, 8}, kEmpty);
  auto d = compare(initial, student, nullptr);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_EQ(d->target_kind, TargetKind::CariesAccess);
  EXPECT_EQ(d->tissue(Material::Caries).target, 16 * kFull);
  EXPECT_EQ(d->tissue(Material::Enamel).target, 24 * kFull);
  EXPECT_EQ(d->total().target_removed, 40 * kFull);
  EXPECT_EQ(d->total().overcut(), 0u);
  EXPECT_EQ(d->healthy().container_removed, 0u);
  EXPECT_TRUE(d->healthy_outside_zone.empty());
  // The enamel below the lesion is not on the way in: cutting it is outside the target.
  student.voxels.setVoxel(4, 4, 0, kEmpty);
  auto deeper = compare(initial, student, nullptr);
  ASSERT_TRUE(deeper.ok());
  EXPECT_EQ(deeper->healthy().container_removed, kFull);
  EXPECT_EQ(deeper->healthy_outside_zone.at(4, 4, 0), kFull);
  expectZonesPartition(*deeper);
}

TEST(ToothDiff, TiltedInsertionAxisSweepsTheLine) {
  // One caries voxel at (4,8,2); along (1,0,1) the line from it meets (5,8,3) .. (9,8,7), five
  // enamel voxels before it leaves the slab at z = 8.
  ToothVolume initial = enamelSlab();
  initial.voxels.setVoxel(4, 8, 2, makeVoxel(Material::Caries));
  auto d = compare(initial, initial, nullptr, 0.0, normalized(Vec3{1, 0, 1}));
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_EQ(d->tissue(Material::Caries).target, kFull);
  EXPECT_EQ(d->tissue(Material::Enamel).target, 5 * kFull);
  // Straight up, the column (4,8,3..7) instead: also five, but other voxels.
  ToothVolume student = initial;
  for (uint32_t k = 1; k <= 5; ++k) student.voxels.setVoxel(4 + k, 8, 2 + k, kEmpty);
  auto tilted = compare(initial, student, nullptr, 0.0, normalized(Vec3{1, 0, 1}));
  auto upright = compare(initial, student, nullptr, 0.0, {0, 0, 1});
  ASSERT_TRUE(tilted.ok() && upright.ok());
  EXPECT_EQ(tilted->total().target_removed, 5 * kFull);
  EXPECT_EQ(tilted->total().container_removed, 0u);
  EXPECT_EQ(upright->total().target_removed, 0u);
  EXPECT_EQ(upright->total().container_removed, 5 * kFull);
}

TEST(ToothDiff, LeewayAroundTheCariesCountedByHand) {
  // A caries voxel in the slab's top layer (z = 7): the column above it is empty space, so the
  // target is that voxel. Within 2 voxels (0.2 mm) of it lie 13 voxels of its layer, 9 of the
  // layer below and 1 two layers down: 23 with itself, so 22 enamel voxels of leeway.
  ToothVolume initial = enamelSlab();
  initial.voxels.setVoxel(8, 8, 7, makeVoxel(Material::Caries));
  auto d = compare(initial, initial, nullptr, 0.2);
  ASSERT_TRUE(d.ok()) << d.message();
  const TissueAmounts& e = d->tissue(Material::Enamel);
  EXPECT_EQ(e.target, 0u);
  EXPECT_EQ(e.leeway, 22 * kFull);
  EXPECT_EQ(e.container, (2047 - 22) * kFull);
  expectZonesPartition(*d);
  // Cutting a voxel at 2 voxels (inside) and one at sqrt(5) voxels (outside).
  ToothVolume student = initial;
  student.voxels.setVoxel(10, 8, 7, kEmpty);
  student.voxels.setVoxel(10, 9, 7, kEmpty);
  auto cut = compare(initial, student, nullptr, 0.2);
  ASSERT_TRUE(cut.ok());
  EXPECT_EQ(cut->tissue(Material::Enamel).leeway_removed, kFull);
  EXPECT_EQ(cut->tissue(Material::Enamel).container_removed, kFull);
  EXPECT_EQ(cut->healthy_outside_zone.voxelCount(), 1u);
  EXPECT_EQ(cut->healthy_outside_zone.at(10, 9, 7), kFull);
}

TEST(ToothDiff, TargetInTheCrownHalf) {
  // Enamel over dentin: the crown faces +z. The ideal removes 4 voxels near the top and 2 near the
  // bottom; the crown half is z >= 4 (the tissue's bricks span z 0..8).
  ToothVolume initial = test::emptyTooth();
  setBox(initial, {0, 0, 0}, {16, 16, 6}, makeVoxel(Material::Dentin));
  setBox(initial, {0, 0, 6}, {16, 16, 8}, makeVoxel(Material::Enamel));
  ToothVolume ideal = initial;
  setBox(ideal, {4, 4, 6}, {6, 6, 7}, kEmpty);
  setBox(ideal, {4, 4, 0}, {6, 5, 1}, kEmpty);
  auto d = compare(initial, initial, &ideal);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_TRUE(d->crown.from_enamel);
  EXPECT_NEAR(d->crown.axis.z, 1.0, 1e-12);
  EXPECT_EQ(d->total().target, 6 * kFull);
  EXPECT_EQ(d->target_in_crown_half, 4 * kFull);
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
  auto level = compareTeeth(t, bigger, nullptr, ZoneOptions{}, names);
  ASSERT_FALSE(level.ok());
  EXPECT_EQ(level.message(), "student.dvol: octree level 5 differs from start.dvol's 4; score volumes of one level");

  ToothVolume finer = t;
  finer.frame.voxel_mm = 0.05;
  auto size = compareTeeth(t, t, &finer, ZoneOptions{}, names);
  ASSERT_FALSE(size.ok());
  EXPECT_EQ(size.message(), "prof.dvol: voxel size 0.05 mm differs from start.dvol's 0.1 mm");

  ToothVolume moved = t;
  moved.frame.origin_mm[1] = 1.5;
  auto origin = compareTeeth(t, moved, nullptr, ZoneOptions{}, names);
  ASSERT_FALSE(origin.ok());
  EXPECT_EQ(origin.message(), "student.dvol: origin y 1.5 mm differs from start.dvol's 0 mm");

  // Default names are the roles.
  auto roles = compareTeeth(t, moved, nullptr, ZoneOptions{});
  ASSERT_FALSE(roles.ok());
  EXPECT_EQ(roles.message().rfind("final: origin y", 0), 0u) << roles.message();
}

}  // namespace
}  // namespace dentsim
