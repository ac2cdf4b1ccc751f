// Tests of src/volume/loose_fragments.cpp: pieces of solid tooth apart from the largest are cleared, counted by hand.
#include "volume/loose_fragments.h"

#include <gtest/gtest.h>

#include "volume/half_fill.h"
#include "volume_fixtures.h"

namespace dentsim {
namespace {

uint64_t countSolid(const BrickVolume& v) {
  uint64_t n = 0;
  for (uint32_t z = 0; z < v.dim(); ++z)
    for (uint32_t y = 0; y < v.dim(); ++y)
      for (uint32_t x = 0; x < v.dim(); ++x) n += isSolidTooth(v.voxel(x, y, z)) ? 1 : 0;
  return n;
}

TEST(LooseFragments, OnePieceIsUnchanged) {
  BrickVolume v(6);
  test::setBox(v, {10, 10, 10}, {30, 30, 40}, makeVoxel(Material::Dentin));
  const BrickVolume before = v;
  const LooseFragments f = dropLooseFragments(v);
  EXPECT_EQ(f.pieces, 0u);
  EXPECT_EQ(f.voxels, 0u);
  EXPECT_EQ(countSolid(v), 20u * 20u * 30u);
  EXPECT_TRUE(v.voxel(10, 10, 10) == before.voxel(10, 10, 10));
}

TEST(LooseFragments, ShellsBesideTheToothAreClearedAndTheToothKept) {
  BrickVolume v(6);
  // The tooth: 20 x 20 x 30 of dentin under 20 x 20 x 5 of enamel (14,000 voxels).
  test::setBox(v, {10, 10, 5}, {30, 30, 35}, makeVoxel(Material::Dentin));
  test::setBox(v, {10, 10, 35}, {30, 30, 40}, makeVoxel(Material::Enamel));
  // A shell of enamel one voxel from the mesial wall, 2 x 12 x 10 = 240 voxels, joined to nothing.
  test::setBox(v, {6, 14, 20}, {8, 26, 30}, makeVoxel(Material::Enamel));
  // A second, 3 x 3 x 3 = 27, touching the tooth only along an edge (not a face: loose).
  test::setBox(v, {30, 30, 12}, {33, 33, 15}, makeVoxel(Material::Dentin));
  // A neighbour touching the shell, and worn grains below half fill bridging shell and tooth: neither joins.
  test::setBox(v, {2, 14, 20}, {6, 26, 30}, makeVoxel(Material::Neighbour));
  test::setBox(v, {8, 14, 20}, {10, 26, 30}, makeVoxel(Material::Enamel, kHalfFill - 1));
  const LooseFragments f = dropLooseFragments(v);
  EXPECT_EQ(f.pieces, 2u);
  EXPECT_EQ(f.voxels, 240u + 27u);
  EXPECT_EQ(f.largest, 240u);
  EXPECT_EQ(countSolid(v), 14000u);
  EXPECT_EQ(voxelMaterial(v.voxel(7, 20, 25)), Material::Empty);
  EXPECT_EQ(voxelMaterial(v.voxel(31, 31, 13)), Material::Empty);
  // What is not solid tooth stays: the neighbour and the grains.
  EXPECT_EQ(voxelMaterial(v.voxel(4, 20, 25)), Material::Neighbour);
  EXPECT_EQ(v.voxel(9, 20, 25), makeVoxel(Material::Enamel, kHalfFill - 1));
  EXPECT_EQ(voxelMaterial(v.voxel(20, 20, 37)), Material::Enamel);
}

TEST(LooseFragments, AFaceJoinKeepsAPieceOnTheTooth) {
  BrickVolume v(6);
  test::setBox(v, {10, 10, 10}, {30, 30, 40}, makeVoxel(Material::Dentin));
  // Held to the wall by one column of half-full voxels: attached, kept.
  test::setBox(v, {6, 14, 20}, {8, 26, 30}, makeVoxel(Material::Enamel));
  test::setBox(v, {8, 20, 25}, {10, 21, 26}, makeVoxel(Material::Enamel, kHalfFill));
  const LooseFragments f = dropLooseFragments(v);
  EXPECT_EQ(f.pieces, 0u);
  EXPECT_EQ(countSolid(v), 20u * 20u * 30u + 240u + 2u);
}

TEST(LooseFragments, EmptyVolumeIsUnchanged) {
  BrickVolume v(5);
  const LooseFragments f = dropLooseFragments(v);
  EXPECT_EQ(f.pieces, 0u);
  EXPECT_EQ(countSolid(v), 0u);
}

}  // namespace
}  // namespace dentsim
