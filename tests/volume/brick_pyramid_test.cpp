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
        const long rim = std::lround((r + 1.0 - d) * 15.5);  // a tissue voxel's fill is 1..31
        if (d < r - 1.0) v.setVoxel(x, y, z, makeVoxel(Material::Enamel));
        else if (d < r + 1.0 && rim > 0) v.setVoxel(x, y, z, makeVoxel(Material::Enamel, uint32_t(rim)));
      }
  test::setBox(v, {50, 50, 50}, {70, 66, 61}, makeVoxel(Material::Pulp));
  std::uniform_int_distribution<uint32_t> coord(0, 127), fill(1, 31), mat(1, 4);
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
  std::uniform_int_distribution<uint32_t> corner(0, 120), size(1, 7), fill(1, 31), mat(0, 4);
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

namespace dentsim {
namespace {

// A solid slab below z = top (voxels 0 .. top-1 full), over a level-7 grid.
BrickVolume slab(uint32_t top) {
  BrickVolume v(7);
  test::setBox(v, {0, 0, 0}, {128, 128, top}, makeVoxel(Material::Dentin));
  return v;
}

TEST(CopyErrorTest, AFlatFaceOnTheCopysGridIsExact) {
  // Full crossing between voxels 95 (31) and 96 (0): t = 1/2, at 96.0. The 2^3 copy: voxel 47
  // (full 94, 95) is 31, voxel 48 is 0: its vertex is at (47.5 + 0.5) * 2 = 96.0 too.
  const BrickVolume full = slab(96);
  const BrickVolume coarse = downsampleVolume(full, 1);
  std::vector<float> error;
  measureCopyError(full, coarse, 1, 4, {}, error);
  ASSERT_EQ(error.size(), 64u);  // 4 regions a side
  for (float e : error) EXPECT_EQ(e, 0.0f);
}

TEST(CopyErrorTest, AFaceBetweenTheCopysVoxelsIsOffByAHandCountedSixteenth) {
  // Full crossing at 97.0 (voxel 96 full, 97 empty). Copy voxel 48 holds four full and four empty
  // voxels: (124 + 4) / 8 = 16, inside; voxel 49 is 0. t = (31 - 32) / (2 * (0 - 16)) = 1/32, so
  // the vertex is at (48.5 + 1/32) * 2 = 97.0625: 0.0625 voxels off, in the regions of z 96..127.
  const BrickVolume full = slab(97);
  const BrickVolume coarse = downsampleVolume(full, 1);
  std::vector<float> error;
  measureCopyError(full, coarse, 1, 4, {}, error);
  for (uint32_t z = 0; z < 4; ++z)
    for (uint32_t i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(error[z * 16 + i], z == 3 ? 0.0625f : 0.0f) << z;
  // Every region flagged walks only the bricks over flagged regions, and must give the same errors.
  std::vector<float> flagged(64, 9.0f);
  measureCopyError(full, coarse, 1, 4, std::vector<uint8_t>(64, 1), flagged);
  EXPECT_EQ(flagged, error);
  // Measuring again only region 0 keeps the others as they were.
  std::vector<uint8_t> only(64, 0);
  only[0] = 1;
  error[63] = 5.0f;
  measureCopyError(full, coarse, 1, 4, only, error);
  EXPECT_EQ(error[63], 5.0f);
  EXPECT_EQ(error[0], 0.0f);
}

TEST(CopyErrorTest, ACopyCoarserThanARegionPutsEachVertexInItsOwnRegion) {
  // The 8^3 copy's bricks span two regions a side. Full crossing at 97.0; copy voxel 11 (z 88..95)
  // is full, voxel 12 (z 96..103) holds one full layer of eight: (64 * 31 + 256) / 512 = 4. Its
  // vertex: t = (31 - 62) / (2 * (4 - 31)) = 31/54, at (11.5 + 31/54) * 8 = 96.593, 0.407 below
  // 97: in the regions of z 96..127 only.
  const BrickVolume full = slab(97);
  const BrickVolume coarse = downsampleVolume(full, 3);
  EXPECT_EQ(coarse.voxel(0, 0, 12), makeVoxel(Material::Dentin, 4));
  std::vector<float> error;
  measureCopyError(full, coarse, 3, 4, {}, error);
  const double want = 97.0 - (11.5 + 31.0 / 54.0) * 8.0;
  for (uint32_t z = 0; z < 4; ++z)
    for (uint32_t i = 0; i < 16; ++i) EXPECT_NEAR(error[z * 16 + i], z == 3 ? want : 0.0, 1e-5) << z;
}

TEST(CopyErrorTest, AThinPlateTheCopyLosesCountsTheWholeWindow) {
  // A plate 2 voxels thick at z 43..44 straddles the 4^3 copy's voxels 10 (z 40..43) and 11 (44..47):
  // each holds one layer, (16 * 31 + 32) / 64 = 8, both outside, and the plate is gone. Its regions
  // count 2^(k+1) = 8.
  BrickVolume full(7);
  test::setBox(full, {0, 0, 43}, {128, 128, 45}, makeVoxel(Material::Enamel));
  const BrickVolume coarse = downsampleVolume(full, 2);
  EXPECT_EQ(coarse.voxel(5, 5, 10), makeVoxel(Material::Enamel, 8));
  std::vector<float> error;
  measureCopyError(full, coarse, 2, 4, {}, error);
  for (uint32_t i = 0; i < 16; ++i) EXPECT_EQ(error[16 + i], 8.0f);
  EXPECT_EQ(error[0], 0.0f);
}

}  // namespace
}  // namespace dentsim
