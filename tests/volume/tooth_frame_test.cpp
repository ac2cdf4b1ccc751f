// Tests for src/volume/tooth_frame.cpp: the nearest quarter turn, turning the voxels and the frame, standing a sideways tooth up, and a neighbour left out of the tooth's box and frame.
#include "volume/tooth_frame.h"

#include <gtest/gtest.h>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

// Where voxel index `i` lies in the scanner frame (the matrix takes voxel centres).
Vec3 scannerOf(const VolumeFrame& f, double x, double y, double z) {
  Vec3 p;
  for (int r = 0; r < 3; ++r)
    p[r] = f.scanner_from_grid[4 * r] * x + f.scanner_from_grid[4 * r + 1] * y + f.scanner_from_grid[4 * r + 2] * z +
           f.scanner_from_grid[4 * r + 3];
  return p;
}

// A 32^3 "tooth" lying on its side: a dentin column along y (roots at +y) with an enamel cap at -y.
ToothVolume sidewaysTooth() {
  ToothVolume t{VolumeFrame::axisAligned(5, 0.5, {-3.0, 1.0, 2.0}), BrickVolume(5)};
  for (uint32_t y = 4; y < 28; ++y)
    for (uint32_t z = 10; z < 20; ++z)
      for (uint32_t x = 12; x < 20; ++x) t.voxels.setVoxel(x, y, z, makeVoxel(y < 10 ? Material::Enamel : Material::Dentin));
  t.frame.source_offset = {2, 3, 4};
  t.frame.source_dims = {20, 25, 26};
  return t;
}

TEST(ToothFrame, TheNearestQuarterTurnStandsTheCrownUp) {
  EXPECT_EQ(nearestQuarterTurn({0, 0, 1}, std::nullopt), kNoTurn);
  EXPECT_EQ(nearestQuarterTurn({0.1, -0.05, 0.99}, std::nullopt), kNoTurn);
  for (const Vec3 crown : {Vec3{0, -1, 0}, Vec3{0, 1, 0}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 0, -1}, Vec3{0.3, -0.9, 0.2}}) {
    const QuarterTurn t = nearestQuarterTurn(crown, std::nullopt);
    const Vec3 up = turned(t, normalized(crown));
    EXPECT_GT(up.z, 0.9) << crown.x << " " << crown.y << " " << crown.z;
  }
  // Crown -y, smallest turn: a quarter turn about x, which leaves x alone.
  const QuarterTurn about_x = nearestQuarterTurn({0, -1, 0}, std::nullopt);
  EXPECT_EQ(turned(about_x, {1, 0, 0}).x, 1.0);
  // With the mesial side known, it goes to -x.
  const QuarterTurn with_mesial = nearestQuarterTurn({0, -1, 0}, Vec3{0, 0, 1});
  EXPECT_EQ(turned(with_mesial, {0, -1, 0}).z, 1.0);
  EXPECT_EQ(turned(with_mesial, {0, 0, 1}).x, -1.0);
}

TEST(ToothFrame, TurningMovesEveryVoxelAndKeepsTheScannerPosition) {
  ToothVolume t = sidewaysTooth();
  t.voxels.setVoxel(13, 5, 11, makeVoxel(Material::Caries, 17));  // one marked voxel
  const ToothVolume before = t;
  const QuarterTurn turn = nearestQuarterTurn({0, -1, 0}, std::nullopt);  // y -> -z ... about x
  turnTooth(t, turn);
  const int64_t n = t.frame.dim();
  // By hand: new[r] = sign (old[from] - c) + c with c = (n - 1) / 2, i.e. old o -> n - 1 - o when flipped.
  uint64_t checked = 0;
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const Vec3 p = turned(turn, Vec3{double(x), double(y), double(z)} - Vec3{15.5, 15.5, 15.5}) + Vec3{15.5, 15.5, 15.5};
        ASSERT_EQ(t.voxels.voxel(uint32_t(p.x), uint32_t(p.y), uint32_t(p.z)), before.voxels.voxel(x, y, z));
        ++checked;
      }
  EXPECT_EQ(checked, uint64_t(n * n * n));
  EXPECT_EQ(t.voxels.materialTotals().voxels, before.voxels.materialTotals().voxels);
  // The marked voxel sits at the same scanner position before and after: an export still overlays.
  const Vec3 p = turned(turn, Vec3{13, 5, 11} - Vec3{15.5, 15.5, 15.5}) + Vec3{15.5, 15.5, 15.5};
  EXPECT_EQ(voxelFill(t.voxels.voxel(uint32_t(p.x), uint32_t(p.y), uint32_t(p.z))), 17u);
  const Vec3 a = scannerOf(before.frame, 13, 5, 11), b = scannerOf(t.frame, p.x, p.y, p.z);
  EXPECT_NEAR(norm(a - b), 0.0, 1e-12);
  // The source box turns with the grid: its voxels keep their counts.
  EXPECT_EQ(t.frame.source_dims[0] * t.frame.source_dims[1] * t.frame.source_dims[2], 20 * 25 * 26);
  EXPECT_EQ(t.frame.tooth.turn, turn);
  // Four quarter turns about one axis give the volume back.
  ToothVolume round = before;
  for (int i = 0; i < 4; ++i) turnTooth(round, turn);
  EXPECT_TRUE(round.voxels == before.voxels);
  EXPECT_EQ(round.frame.scanner_from_grid, before.frame.scanner_from_grid);
  EXPECT_EQ(round.frame.source_offset, before.frame.source_offset);
  EXPECT_FALSE(round.frame.tooth.turned());
}

TEST(ToothFrame, ASidewaysToothIsFoundAndStoodUp) {
  ToothVolume t = sidewaysTooth();
  ASSERT_TRUE(standToothUp(t, {}).ok());
  const ToothAxes& a = t.frame.tooth;
  EXPECT_EQ(a.crown_source, AxisSource::Found);
  EXPECT_GT(a.crown[2], 0.99);  // the enamel cap (at -y before) now on top
  EXPECT_EQ(a.mesial_source, AxisSource::Assumed);
  EXPECT_NEAR(a.mesial[0] * a.crown[0] + a.mesial[1] * a.crown[1] + a.mesial[2] * a.crown[2], 0.0, 1e-12);
  // The enamel lies at the top of the turned grid, dentin below it.
  const auto boxes = tissueVoxelBoxes(t.voxels);
  const VoxelBox& enamel = boxes[size_t(Material::Enamel)];
  const VoxelBox& dentin = boxes[size_t(Material::Dentin)];
  EXPECT_EQ(enamel.hi[2] - enamel.lo[2] + 1, 6);   // y 4..9 became six layers in z
  EXPECT_EQ(dentin.hi[2] - dentin.lo[2] + 1, 18);  // y 10..27
  EXPECT_GT(enamel.lo[2], dentin.hi[2]);
  // The occlusal centre: the middle of the tooth's x,y extent, on top of the enamel.
  ASSERT_TRUE(a.has_occlusal_centre);
  EXPECT_DOUBLE_EQ(a.occlusal_centre_mm[2], t.frame.origin_mm[2] + double(enamel.hi[2] + 1) * 0.5);
}

TEST(ToothFrame, GivenAxesWinAndBadOnesAreNamed) {
  ToothVolume t = sidewaysTooth();
  ToothAxesHint hint;
  hint.crown = Vec3{0, 0, -2};  // the caller says the crown is at -z
  hint.mesial = Vec3{1, 0, 0.5};
  ASSERT_TRUE(standToothUp(t, hint).ok());
  EXPECT_EQ(t.frame.tooth.crown_source, AxisSource::Given);
  EXPECT_EQ(t.frame.tooth.crown, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(t.frame.tooth.mesial, (std::array<double, 3>{-1, 0, 0}));
  EXPECT_EQ(t.frame.tooth.mesial_source, AxisSource::Given);

  ToothVolume u = sidewaysTooth();
  hint = {};
  hint.crown = Vec3{0, 0, 0};
  EXPECT_EQ(standToothUp(u, hint).message(), "--crown-axis: the axis needs three finite numbers, not all zero");
  hint.crown = Vec3{0, 0, 1};
  hint.mesial = Vec3{0, 0, 3};
  EXPECT_EQ(standToothUp(u, hint).message(), "--mesial-axis: lies along the crown axis");

  ToothVolume kept = sidewaysTooth();
  ToothAxesHint keep;
  keep.turn = false;
  ASSERT_TRUE(standToothUp(kept, keep).ok());
  EXPECT_FALSE(kept.frame.tooth.turned());
  EXPECT_LT(kept.frame.tooth.crown[1], -0.99);  // found, not turned: still -y
}

TEST(ToothFrame, ANeighbourBesideTheToothLeavesItsFrameAndBoxAsTheyWere) {
  // A sideways tooth with a neighbour beside it at +x, taller along -y than the tooth's crown, in
  // bricks of its own: standing up, the box and the occlusal centre are the tooth's alone.
  ToothVolume alone = sidewaysTooth();
  ToothVolume beside = sidewaysTooth();
  for (uint32_t y = 0; y < 32; ++y)
    for (uint32_t z = 8; z < 24; ++z)
      for (uint32_t x = 24; x < 32; ++x) beside.voxels.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
  ASSERT_TRUE(standToothUp(alone, {}).ok());
  ASSERT_TRUE(standToothUp(beside, {}).ok());
  const ToothAxes &a = alone.frame.tooth, &b = beside.frame.tooth;
  EXPECT_EQ(b.crown, a.crown);
  EXPECT_EQ(b.turn, a.turn);
  ASSERT_TRUE(b.has_occlusal_centre);
  EXPECT_EQ(b.occlusal_centre_mm, a.occlusal_centre_mm);
  const auto boxes_a = tissueVoxelBoxes(alone.voxels), boxes_b = tissueVoxelBoxes(beside.voxels);
  EXPECT_EQ(boxes_b[0].lo, boxes_a[0].lo);  // index 0: the tooth, not the neighbour
  EXPECT_EQ(boxes_b[0].hi, boxes_a[0].hi);
  // The neighbour keeps a box of its own: 8 x 32 x 16 voxels, however the grid turned.
  const VoxelBox& n = boxes_b[size_t(Material::Neighbour)];
  ASSERT_FALSE(n.empty());
  EXPECT_EQ((n.hi[0] - n.lo[0] + 1) * (n.hi[1] - n.lo[1] + 1) * (n.hi[2] - n.lo[2] + 1), 8 * 32 * 16);
  // The tooth's bricks leave out the bricks that hold only the neighbour.
  const BrickBox tb = toothBricks(beside.voxels), ta = toothBricks(alone.voxels);
  EXPECT_EQ(tb.lo.x, ta.lo.x);
  EXPECT_EQ(tb.hi.x, ta.hi.x);
  EXPECT_EQ(tb.hi.y, ta.hi.y);
  EXPECT_EQ(tb.hi.z, ta.hi.z);
  const BrickBox all = tissueBricks(alone.voxels);  // without neighbours: tissueBricks exactly
  EXPECT_EQ(ta.lo.x, all.lo.x);
  EXPECT_EQ(ta.hi.z, all.hi.z);
}

}  // namespace
}  // namespace dentsim
