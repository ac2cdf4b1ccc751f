// The box the first view frames (app/first_view.h firstViewBox): the treated tooth's, not its neighbours'.
#include <gtest/gtest.h>

#include "app/first_view.h"

namespace dentsim::app {
namespace {

// A 64^3 grid of 0.5 mm voxels (8 bricks a side, 4 mm each) with a tooth block in bricks x 2..3 and
// a neighbour block in bricks x 5..6; both in bricks y 1..2, z 1..2.
struct Scene {
  BrickVolume voxels{6};
  VolumeFrame frame = VolumeFrame::axisAligned(6, 0.5, {0.0, 0.0, 0.0});
  Scene() {
    for (uint32_t z = 8; z < 24; ++z)
      for (uint32_t y = 8; y < 24; ++y) {
        for (uint32_t x = 16; x < 32; ++x) voxels.setVoxel(x, y, z, makeVoxel(Material::Enamel));
        for (uint32_t x = 40; x < 56; ++x) voxels.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
      }
  }
};

TEST(FirstViewBox, FramesTheTreatedToothNotItsNeighbour) {
  const Scene s;
  const TissueBox tooth = firstViewBox(s.voxels, s.frame);
  // Bricks x 2..3 are 8..16 mm; y and z bricks 1..2 are 4..12 mm.
  EXPECT_DOUBLE_EQ(tooth.lo.x, 8.0);
  EXPECT_DOUBLE_EQ(tooth.hi.x, 16.0);
  EXPECT_DOUBLE_EQ(tooth.lo.y, 4.0);
  EXPECT_DOUBLE_EQ(tooth.hi.z, 12.0);
  // All tissue reaches the neighbour's far side, 28 mm; the view would centre between the two.
  EXPECT_DOUBLE_EQ(tissueBox(s.voxels, s.frame).hi.x, 28.0);
}

TEST(FirstViewBox, WithoutANeighbourItIsTheTissueBox) {
  Scene s;
  for (uint32_t z = 8; z < 24; ++z)
    for (uint32_t y = 8; y < 24; ++y)
      for (uint32_t x = 40; x < 56; ++x) s.voxels.setVoxel(x, y, z, makeVoxel(Material::Empty));
  const TissueBox a = firstViewBox(s.voxels, s.frame), b = tissueBox(s.voxels, s.frame);
  EXPECT_EQ(a.lo, b.lo);
  EXPECT_EQ(a.hi, b.hi);
}

}  // namespace
}  // namespace dentsim::app
