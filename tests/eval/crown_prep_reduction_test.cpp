// Tests of measureReduction: a 4 x 4 x 5 mm box tooth cut to a box preparation, every figure counted by hand.
#include "eval/crown_prep_reduction.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace dentsim {
namespace {

constexpr int kLevel = 7;          // 128 voxels a side
constexpr double kVoxelMm = 0.05;  // so the box is 80 x 80 x 100 voxels
const Vec3 kAxis{0, 0, 1};
const Vec3 kMesial{1, 0, 0};       // mesial = +x, distal = -x, buccal = axis x mesial = +y, lingual = -y
// The original box: x, y in [20, 100), z in [10, 110). The margin is at z = 30: heights run from the
// grid origin with centres at (i + 0.5) * 0.05 mm, so 1.5 mm is the face between the centres at z = 29
// (1.475 mm, root) and z = 30 (1.525 mm, measured).
constexpr uint32_t kLo = 20, kHi = 100, kZ0 = 10, kZ1 = 110, kMarginZ = 30;
constexpr double kMarginMm = 1.5;
// Faces' samples by hand: a box's edge and corner voxels have normals at exactly 45 degrees and
// belong to no region, so the top has 78 x 78 samples and each wall 78 (y or x from 21 to 98) by 79
// (z from 30 to 108).
constexpr int kTopFace = 78 * 78;
constexpr int kWallFace = 78 * 79;

void fillBox(BrickVolume& v, std::array<uint32_t, 3> lo, std::array<uint32_t, 3> hi, Material m) {
  for (uint32_t z = lo[2]; z < hi[2]; ++z)
    for (uint32_t y = lo[1]; y < hi[1]; ++y)
      for (uint32_t x = lo[0]; x < hi[0]; ++x) v.setVoxel(x, y, z, makeVoxel(m));
}

BrickVolume originalTooth() {
  BrickVolume v(kLevel);
  fillBox(v, {kLo, kLo, kZ0}, {kHi, kHi, kMarginZ}, Material::Dentin);
  fillBox(v, {kLo, kLo, kMarginZ}, {kHi, kHi, kZ1}, Material::Enamel);
  return v;
}

// The original below the margin; above it, the box with `mesial_cut` voxels off the mesial wall, 20
// (1.0 mm) off the other three and the top lowered by 35 (1.75 mm): z in [30, 75).
BrickVolume preparedTooth(uint32_t mesial_cut = 20, uint32_t occlusal_cut = 35) {
  BrickVolume v(kLevel);
  fillBox(v, {kLo, kLo, kZ0}, {kHi, kHi, kMarginZ}, Material::Dentin);
  fillBox(v, {kLo + 20, kLo + 20, kMarginZ}, {kHi - mesial_cut, kHi - 20, kZ1 - occlusal_cut}, Material::Dentin);
  return v;
}

Result<CrownPrepReduction> measure(const BrickVolume& o, const BrickVolume& p, ReductionBands bands = {}) {
  return measureReduction(o, p, kVoxelMm, kAxis, kMesial, kMarginMm, bands);
}

// The median is the middle reading (nearest rank): a quarter of the top (x in [40, 50) of [40, 80))
// cut 1.25 mm deeper than the rest reads 3.0 there: the mean is 0.75 x 1.75 + 0.25 x 3.0 = 2.0625,
// the median 1.75.
TEST(CrownPrepReductionTest, TheMedianIsTheMiddleReading) {
  BrickVolume prepared = preparedTooth();
  for (uint32_t z = kZ1 - 60; z < kZ1 - 35; ++z)
    for (uint32_t y = kLo + 20; y < kHi - 20; ++y)
      for (uint32_t x = kLo + 20; x < kLo + 30; ++x) prepared.setVoxel(x, y, z, makeVoxel(Material::Empty));
  const auto r = measure(originalTooth(), prepared);
  ASSERT_TRUE(r.ok()) << r.message();
  // Less the two rays that land in the deep quarter's inner corners, where its floor meets the
  // step and the box's side at once: that voxel faces the side more than up, a wall's, so those
  // gauges read no table (unreached).
  EXPECT_EQ(r->occlusal.samples, 40 * 40 - 2);
  EXPECT_NEAR(r->occlusal.mean_mm, 0.75 * 1.75 + 0.25 * 3.0, kVoxelMm);
  EXPECT_NEAR(r->occlusal.median_mm, 1.75, kVoxelMm);
  EXPECT_NEAR(r->occlusal.max_mm, 3.0, kVoxelMm);
}

TEST(CrownPrepReductionTest, BoxPreparationMeasuresItsCuts) {
  const auto r = measure(originalTooth(), preparedTooth());
  ASSERT_TRUE(r.ok()) << r.message();
  // Only the samples whose inward ray meets the preparation count: the top over the 40 x 40
  // footprint x, y in [40, 80); on each wall the 40 columns over it by the 45 heights z in [30, 75).
  // The wall above z = 74 and the top's rim were taken off whole: 78*78 - 1600 + 4 * (78*79 - 1800).
  EXPECT_EQ(r->occlusal.samples, 40 * 40);
  EXPECT_NEAR(r->occlusal.mean_mm, 1.75, kVoxelMm);
  EXPECT_NEAR(r->occlusal.median_mm, 1.75, kVoxelMm);
  EXPECT_NEAR(r->occlusal.min_mm, 1.75, kVoxelMm);
  EXPECT_NEAR(r->occlusal.max_mm, 1.75, kVoxelMm);
  EXPECT_EQ(r->occlusal.under_share, 0.0);
  EXPECT_EQ(r->occlusal.over_share, 0.0);
  for (AxialWall w : {AxialWall::Mesial, AxialWall::Distal, AxialWall::Buccal, AxialWall::Lingual}) {
    SCOPED_TRACE(int(w));
    EXPECT_EQ(r->wall(w).samples, 40 * 45);
    EXPECT_NEAR(r->wall(w).mean_mm, 1.0, kVoxelMm);
    EXPECT_NEAR(r->wall(w).min_mm, 1.0, kVoxelMm);
    EXPECT_NEAR(r->wall(w).max_mm, 1.0, kVoxelMm);
    EXPECT_EQ(r->wall(w).under_share, 0.0);  // 1.0 mm sits on the band's lo and is in it
    EXPECT_EQ(r->wall(w).over_share, 0.0);
  }
  EXPECT_EQ(r->unreached, kTopFace - 1600 + 4 * (kWallFace - 1800));
  EXPECT_TRUE(r->under_voxels.empty());
  EXPECT_TRUE(r->over_voxels.empty());
}

TEST(CrownPrepReductionTest, NarrowerBandsMarkTheSameCutsUnderAndOver) {
  ReductionBands bands;
  bands.occlusal_lo = 1.8;  // 1.75 is under
  bands.axial_hi = 0.9;     // 1.0 is over
  bands.axial_lo = 0.5;
  const auto r = measure(originalTooth(), preparedTooth(), bands);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->occlusal.under_share, 1.0);
  EXPECT_EQ(r->wall(AxialWall::Buccal).over_share, 1.0);
  EXPECT_EQ(r->under_voxels.size(), size_t(40 * 40));
  EXPECT_EQ(r->over_voxels.size(), size_t(4 * 40 * 45));
  // The top centre (60, 60, 109) is under, the distal wall's (20, 60, 50) over.
  EXPECT_NE(std::find(r->under_voxels.begin(), r->under_voxels.end(), reductionVoxelKey(60, 60, 109)), r->under_voxels.end());
  EXPECT_NE(std::find(r->over_voxels.begin(), r->over_voxels.end(), reductionVoxelKey(20, 60, 50)), r->over_voxels.end());
}

TEST(CrownPrepReductionTest, HalfMillimetreOffOneWallIsUnderOnThatWallOnly) {
  const auto r = measure(originalTooth(), preparedTooth(10));
  ASSERT_TRUE(r.ok()) << r.message();
  const ReductionStats& mesial = r->wall(AxialWall::Mesial);
  EXPECT_EQ(mesial.samples, 40 * 45);
  EXPECT_NEAR(mesial.mean_mm, 0.5, kVoxelMm);
  EXPECT_EQ(mesial.under_share, 1.0);
  EXPECT_EQ(mesial.over_share, 0.0);
  EXPECT_EQ(r->wall(AxialWall::Distal).samples, 40 * 45);
  // The footprint is now x in [40, 90): 50 columns on the buccal and lingual walls.
  EXPECT_EQ(r->wall(AxialWall::Buccal).samples, 50 * 45);
  EXPECT_EQ(r->wall(AxialWall::Lingual).samples, 50 * 45);
  EXPECT_EQ(r->occlusal.samples, 50 * 40);
  for (AxialWall w : {AxialWall::Distal, AxialWall::Buccal, AxialWall::Lingual}) {
    SCOPED_TRACE(int(w));
    EXPECT_NEAR(r->wall(w).mean_mm, 1.0, kVoxelMm);
    EXPECT_EQ(r->wall(w).under_share, 0.0);
    EXPECT_EQ(r->wall(w).over_share, 0.0);
  }
  EXPECT_EQ(r->occlusal.under_share, 0.0);
  EXPECT_EQ(r->under_voxels.size(), size_t(40 * 45));
  EXPECT_NE(std::find(r->under_voxels.begin(), r->under_voxels.end(), reductionVoxelKey(99, 60, 50)), r->under_voxels.end());
  EXPECT_TRUE(r->over_voxels.empty());
}

TEST(CrownPrepReductionTest, OcclusalLoweredTwoAndAHalfMillimetresIsOver) {
  const auto r = measure(originalTooth(), preparedTooth(20, 50));  // top at z = 59: 50 voxels down
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->occlusal.samples, 40 * 40);
  EXPECT_NEAR(r->occlusal.mean_mm, 2.5, kVoxelMm);
  EXPECT_EQ(r->occlusal.over_share, 1.0);
  EXPECT_EQ(r->occlusal.under_share, 0.0);
  EXPECT_EQ(r->wall(AxialWall::Mesial).samples, 40 * 30);  // z in [30, 60)
  EXPECT_EQ(r->wall(AxialWall::Mesial).over_share, 0.0);
  EXPECT_EQ(r->over_voxels.size(), size_t(40 * 40));
  EXPECT_TRUE(r->under_voxels.empty());
}

TEST(CrownPrepReductionTest, WallsFollowTheMesialDirection) {
  // With mesial = +y, buccal = axis x mesial = -x: the +x face cut 0.5 mm is the lingual wall.
  const auto r = measureReduction(originalTooth(), preparedTooth(10), kVoxelMm, kAxis, Vec3{0, 1, 0}, kMarginMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_NEAR(r->wall(AxialWall::Lingual).mean_mm, 0.5, kVoxelMm);
  EXPECT_EQ(r->wall(AxialWall::Lingual).under_share, 1.0);
  EXPECT_NEAR(r->wall(AxialWall::Buccal).mean_mm, 1.0, kVoxelMm);
  EXPECT_EQ(r->wall(AxialWall::Buccal).under_share, 0.0);
  EXPECT_EQ(r->wall(AxialWall::Mesial).samples, 50 * 45);
  EXPECT_EQ(r->wall(AxialWall::Distal).samples, 50 * 45);
}

TEST(CrownPrepReductionTest, NeighbourTouchingTheMesialWallChangesNothing) {
  BrickVolume original = originalTooth();
  BrickVolume prepared = preparedTooth(10);
  const auto alone = measure(original, prepared);
  fillBox(original, {kHi, kLo, kZ0}, {kHi + 10, kHi, kZ1}, Material::Neighbour);
  fillBox(prepared, {kHi, kLo, kZ0}, {kHi + 10, kHi, kZ1}, Material::Neighbour);
  const auto beside = measure(original, prepared);
  ASSERT_TRUE(alone.ok()) << alone.message();
  ASSERT_TRUE(beside.ok()) << beside.message();
  EXPECT_EQ(beside->occlusal.samples, alone->occlusal.samples);
  EXPECT_EQ(beside->occlusal.mean_mm, alone->occlusal.mean_mm);
  for (size_t w = 0; w < 4; ++w) {
    EXPECT_EQ(beside->axial[w].samples, alone->axial[w].samples) << w;
    EXPECT_EQ(beside->axial[w].mean_mm, alone->axial[w].mean_mm) << w;
    EXPECT_EQ(beside->axial[w].under_share, alone->axial[w].under_share) << w;
  }
  EXPECT_EQ(beside->unreached, alone->unreached);
  EXPECT_EQ(beside->under_voxels, alone->under_voxels);
  EXPECT_EQ(beside->over_voxels, alone->over_voxels);
}

TEST(CrownPrepReductionTest, UnpreparedToothIsZeroAndAllUnder) {
  const BrickVolume tooth = originalTooth();
  const auto r = measure(tooth, tooth);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->occlusal.samples, kTopFace);
  EXPECT_EQ(r->occlusal.mean_mm, 0.0);
  EXPECT_EQ(r->occlusal.max_mm, 0.0);
  EXPECT_EQ(r->occlusal.under_share, 1.0);
  for (size_t w = 0; w < 4; ++w) {
    EXPECT_EQ(r->axial[w].samples, kWallFace) << w;
    EXPECT_EQ(r->axial[w].mean_mm, 0.0) << w;
    EXPECT_EQ(r->axial[w].under_share, 1.0) << w;
    EXPECT_EQ(r->axial[w].over_share, 0.0) << w;
  }
  EXPECT_EQ(r->unreached, 0);
  EXPECT_EQ(r->under_voxels.size(), size_t(kTopFace + 4 * kWallFace));
}

bool listed(const std::vector<uint64_t>& keys, uint32_t x, uint32_t y, uint32_t z) {
  return std::binary_search(keys.begin(), keys.end(), reductionVoxelKey(x, y, z));
}

TEST(CrownPrepReductionTest, PreparedSideOfTheExactBoxIsAllWithin) {
  const auto r = measure(originalTooth(), preparedTooth());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->prepared_under.empty());
  EXPECT_TRUE(r->prepared_over.empty());
  // The rays meet the preparation's whole surface above the margin, each voxel once: its top layer
  // (z = 74, 40 x 40) and the ring of each layer below it down to z = 30 (44 layers of 4 * 39 voxels).
  EXPECT_EQ(r->prepared_within.size(), size_t(40 * 40 + 44 * 4 * 39));
  EXPECT_TRUE(std::is_sorted(r->prepared_within.begin(), r->prepared_within.end()));
  EXPECT_TRUE(listed(r->prepared_within, 60, 60, 74));  // the top's centre
  EXPECT_TRUE(listed(r->prepared_within, 79, 60, 50));  // the mesial wall
  EXPECT_TRUE(listed(r->prepared_within, 40, 40, 30));  // a corner at the margin
  EXPECT_FALSE(listed(r->prepared_within, 60, 60, 50));  // inside
}

TEST(CrownPrepReductionTest, PreparedSideOfAnUnderReducedWallIsUnder) {
  const auto r = measure(originalTooth(), preparedTooth(10));  // the mesial wall 0.5 mm in, at x = 89
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->prepared_over.empty());
  // The mesial samples' rays meet the wall x = 89 over y in [40, 80) and z in [30, 75), once each.
  EXPECT_EQ(r->prepared_under.size(), size_t(40 * 45));
  for (uint64_t key : r->prepared_under) EXPECT_EQ(key & 0x1FFFFF, 89u);
  EXPECT_TRUE(listed(r->prepared_under, 89, 60, 50));
  EXPECT_FALSE(listed(r->prepared_within, 89, 60, 50));
  EXPECT_TRUE(listed(r->prepared_within, 40, 60, 50));  // the distal wall, 1.0 mm in
  // The mesial wall's buccal edge is met by the under mesial rays and the within buccal ones: in both.
  EXPECT_TRUE(listed(r->prepared_under, 89, 79, 50));
  EXPECT_TRUE(listed(r->prepared_within, 89, 79, 50));
}

TEST(CrownPrepReductionTest, ErrorsNameTheirCause) {
  const BrickVolume tooth = originalTooth();
  const auto grids = measure(tooth, BrickVolume(kLevel - 1));
  ASSERT_FALSE(grids.ok());
  EXPECT_NE(grids.message().find("different grids"), std::string::npos) << grids.message();
  const auto none = measure(BrickVolume(kLevel), tooth);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no tooth"), std::string::npos) << none.message();
  BrickVolume neighbour_only(kLevel);
  fillBox(neighbour_only, {0, 0, 0}, {8, 8, 8}, Material::Neighbour);
  const auto only_neighbour = measure(neighbour_only, tooth);
  ASSERT_FALSE(only_neighbour.ok());
  EXPECT_NE(only_neighbour.message().find("no tooth"), std::string::npos) << only_neighbour.message();
  const auto high = measureReduction(tooth, tooth, kVoxelMm, kAxis, kMesial, 5.5, {});  // top centre at 5.475 mm
  ASSERT_FALSE(high.ok());
  EXPECT_NE(high.message().find("above the margin"), std::string::npos) << high.message();
  const auto along = measureReduction(tooth, tooth, kVoxelMm, kAxis, Vec3{0, 0, 2}, kMarginMm, {});
  ASSERT_FALSE(along.ok());
  EXPECT_NE(along.message().find("mesial"), std::string::npos) << along.message();
  // Just under the top centre's height the top face is still above the margin.
  EXPECT_TRUE(measureReduction(tooth, tooth, kVoxelMm, kAxis, kMesial, 5.45, {}).ok());
}

}  // namespace
}  // namespace dentsim
