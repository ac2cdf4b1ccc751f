// Tests of the cut zone: the caries' access marked along upright and slanted axes, the leeway's voxels counted by hand, the allowed zone's grid, and a neighbour never in it.
#include "volume/cut_zone.h"

#include <gtest/gtest.h>

#include "volume_fixtures.h"

namespace dentsim {
namespace {

using test::setBox;

bool marked(const TargetMasks& m, uint32_t x, uint32_t y, uint32_t z) {
  const TargetMasks::Mask* mask = m.find({x >> 3, y >> 3, z >> 3});
  return mask && TargetMasks::test(*mask, layout::brickCoordToOffset(x & 7u, y & 7u, z & 7u));
}

uint64_t countMarked(const TargetMasks& m, uint32_t dim) {
  uint64_t n = 0;
  for (uint32_t z = 0; z < dim; ++z)
    for (uint32_t y = 0; y < dim; ++y)
      for (uint32_t x = 0; x < dim; ++x) n += marked(m, x, y, z) ? 1u : 0u;
  return n;
}

// Enamel z 0..8 over a 16 x 16 base, a 32^3 grid.
BrickVolume slab() {
  BrickVolume v(5);
  setBox(v, {0, 0, 0}, {16, 16, 8}, makeVoxel(Material::Enamel));
  return v;
}

TEST(CutZone, UprightAccessIsTheColumnOverTheCaries) {
  BrickVolume v = slab();
  setBox(v, {4, 4, 2}, {6, 5, 4}, makeVoxel(Material::Caries));  // 2 x 1 x 2 voxels
  TargetMasks m(v.brickDim());
  markCariesAccess(v, {0, 0, 1}, 1, &m);
  // The column over x 4..5, y 4, from z 2 up to the grid's top (the tissue's bricks end at z 8,
  // and one brick of reach beyond: z 16): 2 x 14 voxels.
  for (uint32_t z = 2; z < 16; ++z) {
    EXPECT_TRUE(marked(m, 4, 4, z)) << z;
    EXPECT_TRUE(marked(m, 5, 4, z)) << z;
  }
  EXPECT_FALSE(marked(m, 4, 4, 1));  // below the lesion: not on the way in
  EXPECT_FALSE(marked(m, 6, 4, 5));
  EXPECT_EQ(countMarked(m, v.dim()), 2u * 14u);
}

TEST(CutZone, SlantedAccessFollowsTheAxis) {
  BrickVolume v = slab();
  v.setVoxel(4, 8, 2, makeVoxel(Material::Caries));
  TargetMasks m(v.brickDim());
  markCariesAccess(v, normalized(Vec3{1, 0, 1}), 1, &m);
  // (4+k, 8, 2+k) for k = 0 .. 13 lie within the marked bricks (z < 16, x < 24).
  for (uint32_t k = 0; k < 14; ++k) EXPECT_TRUE(marked(m, 4 + k, 8, 2 + k)) << k;
  EXPECT_FALSE(marked(m, 4, 8, 3));
  EXPECT_FALSE(marked(m, 3, 8, 1));
  EXPECT_EQ(countMarked(m, v.dim()), 14u);
  // The other way round, down and to -y at a shallow slant: one voxel per slice of y.
  TargetMasks n(v.brickDim());
  markCariesAccess(v, normalized(Vec3{0, -2, 1}), 1, &n);
  EXPECT_TRUE(marked(n, 4, 8, 2));
  EXPECT_TRUE(marked(n, 4, 7, 2));   // half a voxel up after one step: rounds down
  EXPECT_TRUE(marked(n, 4, 6, 3));
  EXPECT_TRUE(marked(n, 4, 4, 4));
  EXPECT_FALSE(marked(n, 4, 9, 2));
}

TEST(CutZone, NoCariesMarksNothing) {
  const BrickVolume v = slab();
  TargetMasks m(v.brickDim());
  markCariesAccess(v, {0, 0, 1}, 1, &m);
  EXPECT_TRUE(m.empty());
}

TEST(CutZone, LeewayCountedByHand) {
  // One target voxel at (8,8,8) in a 32^3 grid: the voxels within 2 of it are the 33 lattice points
  // of a ball of radius 2 (1 + 6 + 12 + 8 + 6 at squared distances 0, 1, 2, 3, 4).
  BrickVolume v(5);
  TargetMasks m(v.brickDim());
  m.set({1, 1, 1}, layout::brickCoordToOffset(0, 0, 0));
  LeewayField leeway(m, 2.0);
  uint64_t near = 0;
  for (uint32_t bz = 0; bz < 4; ++bz)
    for (uint32_t by = 0; by < 4; ++by)
      for (uint32_t bx = 0; bx < 4; ++bx) {
        if (!leeway.inBand({bx, by, bz})) continue;
        for (uint8_t b : leeway.near({bx, by, bz})) near += b;
      }
  EXPECT_EQ(near, 33u);
  EXPECT_FALSE(leeway.inBand({3, 3, 3}));
  // Just under two voxels, the distance-2 points drop out.
  LeewayField tighter(m, 1.99);
  uint64_t fewer = 0;
  for (uint32_t bz = 0; bz < 2; ++bz)
    for (uint32_t by = 0; by < 2; ++by)
      for (uint32_t bx = 0; bx < 2; ++bx)
        if (tighter.inBand({bx, by, bz}))
          for (uint8_t b : tighter.near({bx, by, bz})) fewer += b;
  EXPECT_EQ(fewer, 27u);
}

TEST(CutZone, ZoneGridAllowsTargetLeewayAndEmptySpace) {
  BrickVolume v = slab();
  v.setVoxel(8, 8, 7, makeVoxel(Material::Caries));
  TargetMasks m(v.brickDim());
  markCariesAccess(v, {0, 0, 1}, 1, &m);
  LeewayField leeway(m, 2.0);
  const ZoneGrid grid(v, m, leeway, {0, 0, 0}, {16, 16, 16});
  EXPECT_TRUE(grid.target(8, 8, 7));
  EXPECT_TRUE(grid.target(8, 8, 12));      // the column above: empty space on the way in
  EXPECT_TRUE(grid.allowed(10, 8, 7));     // 2 voxels away: leeway
  EXPECT_FALSE(grid.target(10, 8, 7));
  EXPECT_FALSE(grid.allowed(11, 8, 7));    // 3 voxels away: enamel to keep
  EXPECT_TRUE(grid.allowed(11, 8, 9));     // no tissue there
  EXPECT_FALSE(grid.allowed(20, 8, 7));    // outside the box
}

TEST(CutZone, ANeighbourIsNeverTargetNorAllowed) {
  BrickVolume v = slab();
  v.setVoxel(8, 8, 7, makeVoxel(Material::Caries));
  // A neighbour's overhang across the caries' column (z 10..11) and a block beside it, 2 voxels
  // from the caries: within the leeway.
  setBox(v, {7, 7, 10}, {10, 10, 12}, makeVoxel(Material::Neighbour));
  setBox(v, {10, 8, 7}, {12, 9, 8}, makeVoxel(Material::Neighbour));
  TargetMasks m(v.brickDim());
  markCariesAccess(v, {0, 0, 1}, 1, &m);
  // The column is the caries and the space above it, less the two neighbour voxels on it: z 7..23
  // (the tissue's bricks, the neighbour's among them, end at z 16, and one brick of reach beyond),
  // 17 voxels, with z 10 and 11 left out.
  EXPECT_TRUE(marked(m, 8, 8, 9));
  EXPECT_FALSE(marked(m, 8, 8, 10));
  EXPECT_FALSE(marked(m, 8, 8, 11));
  EXPECT_TRUE(marked(m, 8, 8, 12));
  EXPECT_EQ(countMarked(m, v.dim()), 17u - 2u);
  LeewayField leeway(m, 2.0);
  const ZoneGrid grid(v, m, leeway, {0, 0, 0}, {16, 16, 16});
  EXPECT_FALSE(grid.allowed(8, 8, 10));  // on the line, but another tooth
  EXPECT_FALSE(grid.allowed(10, 8, 7));  // 2 voxels away: enamel there would be leeway
  EXPECT_TRUE(grid.allowed(9, 8, 7));    // the enamel beside the caries still is
}

}  // namespace
}  // namespace dentsim
