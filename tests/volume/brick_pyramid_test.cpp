// Tests of the coarse copies: the brick-wise code against the voxel-by-voxel rule, the update against a new copy, and hand counts.
#include "volume/brick_pyramid.h"

#include <random>

#include <gtest/gtest.h>

#include "volume/volume_fixtures.h"

namespace dentsim {
namespace {

// A level-7 tooth-like volume: a solid dentin chunk (a chunk tile), an enamel ball with partial
// fills at its rim, a pulp box, caries specks and random voxels of every tissue.
BrickVolume mixedVolume(uint32_t seed) {
  BrickVolume v(7);
  v.setChunkUniform(1, 0, 0, makeVoxel(Material::Dentin));
  std::mt19937 rng(seed);
  const double r = 30.0;
  for (uint32_t z = 20; z < 100; ++z)
    for (uint32_t y = 20; y < 100; ++y)
      for (uint32_t x = 20; x < 100; ++x) {
        const double d = std::sqrt((x - 60.0) * (x - 60.0) + (y - 62.0) * (y - 62.0) + (z - 58.0) * (z - 58.0));
        if (d < r - 1.0) v.setVoxel(x, y, z, makeVoxel(Material::Enamel));
        else if (d < r + 1.0) v.setVoxel(x, y, z, makeVoxel(Material::Enamel, uint32_t(std::lround((r + 1.0 - d) * 15.5))));
      }
  test::setBox(v, {50, 50, 50}, {70, 66, 61}, makeVoxel(Material::Pulp));
  std::uniform_int_distribution<uint32_t> coord(0, 127), fill(0, 31), mat(1, 4);
  for (int i = 0; i < 3000; ++i) v.setVoxel(coord(rng), coord(rng), coord(rng), makeVoxel(Material(mat(rng)), fill(rng)));
  return v;
}

void expectMatchesReference(const BrickVolume& fine, const BrickVolume& coarse, uint32_t k) {
  ASSERT_EQ(coarse.level(), fine.level() - int(k));
  size_t mismatches = 0;
  for (uint32_t z = 0; z < coarse.dim(); ++z)
    for (uint32_t y = 0; y < coarse.dim(); ++y)
      for (uint32_t x = 0; x < coarse.dim(); ++x)
        if (coarse.voxel(x, y, z) != coarseVoxelReference(fine, x << k, y << k, z << k, k) && ++mismatches < 5)
          ADD_FAILURE() << "k " << k << " voxel (" << x << ", " << y << ", " << z << ")";
  EXPECT_EQ(mismatches, 0u);
}

TEST(BrickPyramidTest, OneCoarseVoxelCountedByHand) {
  BrickVolume v(4);
  // Beneath coarse voxel (0,0,0) at k = 1: three full enamel voxels (93), four dentin at fill 20
  // (80) and one empty. Mean fill (173 + 4) / 8 = 22; enamel has the larger sum.
  v.setVoxel(0, 0, 0, makeVoxel(Material::Enamel));
  v.setVoxel(1, 0, 0, makeVoxel(Material::Enamel));
  v.setVoxel(0, 1, 0, makeVoxel(Material::Enamel));
  v.setVoxel(1, 1, 0, makeVoxel(Material::Dentin, 20));
  v.setVoxel(0, 0, 1, makeVoxel(Material::Dentin, 20));
  v.setVoxel(1, 0, 1, makeVoxel(Material::Dentin, 20));
  v.setVoxel(0, 1, 1, makeVoxel(Material::Dentin, 20));
  // Beneath (1,0,0): one pulp voxel of fill 3: (3 + 4) / 8 rounds to 0, so it is empty.
  v.setVoxel(2, 0, 0, makeVoxel(Material::Pulp, 3));
  // Beneath (2,0,0): enamel 16 and dentin 16 tie; the lower code (enamel) wins; (32 + 4) / 8 = 4.
  v.setVoxel(4, 0, 0, makeVoxel(Material::Enamel, 16));
  v.setVoxel(5, 0, 0, makeVoxel(Material::Dentin, 16));
  const BrickVolume c = downsampleVolume(v, 1);
  EXPECT_EQ(c.voxel(0, 0, 0), makeVoxel(Material::Enamel, 22));
  EXPECT_EQ(c.voxel(1, 0, 0), makeVoxel(Material::Empty));
  EXPECT_EQ(c.voxel(2, 0, 0), makeVoxel(Material::Enamel, 4));
  EXPECT_EQ(c.voxel(3, 3, 3), makeVoxel(Material::Empty));
}

TEST(BrickPyramidTest, EveryFactorEqualsTheVoxelRule) {
  const BrickVolume fine = mixedVolume(7);
  for (uint32_t k = 1; k <= 3; ++k) expectMatchesReference(fine, downsampleVolume(fine, k), k);
}

TEST(BrickPyramidTest, AWholeTileChunkStaysATile) {
  BrickVolume fine(8);
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 2; ++y)
      for (uint32_t x = 0; x < 2; ++x) fine.setChunkUniform(x, y, z, makeVoxel(Material::Dentin));
  const BrickVolume c = downsampleVolume(fine, 1);
  EXPECT_EQ(c.chunkTile(0, 0, 0), makeVoxel(Material::Dentin));
  EXPECT_EQ(c.chunkTile(1, 1, 1), makeVoxel(Material::Empty));
  EXPECT_EQ(c.stats().dense_bricks, 0u);
}

TEST(BrickPyramidTest, UpdatingTheChangedBricksEqualsANewCopy) {
  BrickVolume fine = mixedVolume(11);
  std::array<BrickVolume, 3> coarse{downsampleVolume(fine, 1), downsampleVolume(fine, 2), downsampleVolume(fine, 3)};
  std::mt19937 rng(5);
  std::uniform_int_distribution<uint32_t> corner(0, 120), size(1, 7), fill(0, 31), mat(0, 4);
  for (int round = 0; round < 20; ++round) {
    // A drill's worth of change: a small box set to one voxel value, and the bricks it touched.
    const std::array<uint32_t, 3> lo{corner(rng), corner(rng), corner(rng)};
    const std::array<uint32_t, 3> hi{lo[0] + size(rng), lo[1] + size(rng), lo[2] + size(rng)};
    test::setBox(fine, lo, hi, makeVoxel(Material(mat(rng)), fill(rng)));
    std::vector<BrickCoord> dirty;
    for (uint32_t z = lo[2] / 8; z <= (hi[2] - 1) / 8; ++z)
      for (uint32_t y = lo[1] / 8; y <= (hi[1] - 1) / 8; ++y)
        for (uint32_t x = lo[0] / 8; x <= (hi[0] - 1) / 8; ++x) dirty.push_back({x, y, z});
    for (uint32_t k = 1; k <= 3; ++k) {
      const std::vector<BrickCoord> changed = downsampleBricks(fine, k, dirty, coarse[k - 1]);
      EXPECT_FALSE(changed.empty());
      for (const BrickCoord& c : changed) {
        EXPECT_LT(c.x, coarse[k - 1].brickDim());
        EXPECT_LT(c.z, coarse[k - 1].brickDim());
      }
    }
  }
  for (uint32_t k = 1; k <= 3; ++k) {
    EXPECT_TRUE(coarse[k - 1] == downsampleVolume(fine, k)) << "k " << k;
    expectMatchesReference(fine, coarse[k - 1], k);
  }
}

}  // namespace
}  // namespace dentsim
