// Tests that the scripted paths find the treated tooth, not an adjacent one: a ray into the tooth passes through a neighbour, and the tooth's box leaves a neighbour out.
#include <gtest/gtest.h>

#include "sim/pocket_planner.h"
#include "sim/scripted_paths.h"
#include "sim_fixtures.h"

namespace dentsim {
namespace {

// Sets every voxel of the box [lo, hi) to v.
void setBox(BrickVolume& v, std::array<uint32_t, 3> lo, std::array<uint32_t, 3> hi, Voxel value) {
  for (uint32_t z = lo[2]; z < hi[2]; ++z)
    for (uint32_t y = lo[1]; y < hi[1]; ++y)
      for (uint32_t x = lo[0]; x < hi[0]; ++x) v.setVoxel(x, y, z, value);
}

TEST(NeighbourPaths, ARayPassesThroughANeighbourToTheTooth) {
  // Dentin up to z = 0.8 mm (voxel 64). A neighbour's overhang hangs over it at z 1.0..1.1 mm
  // (voxels 80..87), and another lies on it, z 0.8..0.9 mm (voxels 64..71), elsewhere.
  test::Block b = test::flatBlock(Material::Dentin);
  setBox(b.volume, {40, 40, 80}, {88, 88, 88}, makeVoxel(Material::Neighbour));
  setBox(b.volume, {8, 8, 64}, {32, 32, 72}, makeVoxel(Material::Neighbour));
  TissueRay ray(b.volume, b.frame);
  // Under the overhang: the dentin's surface 0.7 mm down, not the neighbour's 0.4 mm.
  auto through = ray.first({0.8, 0.8, 1.5}, {0, 0, -1}, 1.5);
  ASSERT_TRUE(through.has_value());
  EXPECT_NEAR(through->distance_mm, 0.7, 0.5 * test::Block::kVoxel);
  EXPECT_EQ(through->material, Material::Dentin);
  // Where the neighbour lies on the tooth, the tooth begins where the neighbour ends, within a voxel.
  auto touching = ray.first({0.25, 0.25, 1.5}, {0, 0, -1}, 1.5);
  ASSERT_TRUE(touching.has_value());
  EXPECT_NEAR(touching->distance_mm, 0.7, 1.5 * test::Block::kVoxel);
  EXPECT_EQ(touching->material, Material::Dentin);
  // Where there is no neighbour the ray is what it was: the bisected surface.
  auto plain = ray.first({1.4, 0.2, 1.5}, {0, 0, -1}, 1.5);
  ASSERT_TRUE(plain.has_value());
  EXPECT_NEAR(plain->distance_mm, 0.7, 0.5 * test::Block::kVoxel);
  // A ray that meets only the neighbour meets nothing.
  EXPECT_FALSE(ray.first({0.8, 0.8, 1.5}, {0, 0, -1}, 0.5).has_value());
}

TEST(NeighbourPaths, TheToothsBoxLeavesANeighbourOut) {
  // A tooth in bricks 0..1 of a 32^3 grid of 0.1 mm voxels, a neighbour in bricks 2..3 along x.
  const VolumeFrame frame = VolumeFrame::axisAligned(5, 0.1, {0, 0, 0});
  BrickVolume alone(5);
  setBox(alone, {2, 2, 0}, {14, 14, 12}, makeVoxel(Material::Enamel));
  BrickVolume beside = alone;
  setBox(beside, {17, 0, 0}, {32, 16, 20}, makeVoxel(Material::Neighbour));
  const TissueBox tooth = toothBox(beside, frame), lone = toothBox(alone, frame), all = tissueBox(beside, frame);
  EXPECT_EQ(tooth.lo.x, lone.lo.x);
  EXPECT_EQ(tooth.hi.x, lone.hi.x);
  EXPECT_EQ(tooth.hi.z, lone.hi.z);
  EXPECT_NEAR(tooth.hi.x, 1.6, 1e-12);  // the tooth's two bricks: x 0..1.6 mm
  EXPECT_NEAR(all.hi.x, 3.2, 1e-12);    // every tissue: the neighbour's bricks too
  EXPECT_NEAR(all.hi.z, 2.4, 1e-12);
  // Without a neighbour the tooth's box is the tissue's box.
  const TissueBox plain = tissueBox(alone, frame);
  EXPECT_EQ(lone.lo.x, plain.lo.x);
  EXPECT_EQ(lone.hi.x, plain.hi.x);
  EXPECT_EQ(lone.hi.z, plain.hi.z);
}

}  // namespace
}  // namespace dentsim
