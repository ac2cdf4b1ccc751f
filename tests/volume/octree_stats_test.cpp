// Tests for src/volume/octree_stats.cpp: hand-counted octrees and a brute-force reference.
#include "volume/octree_stats.h"

#include <gtest/gtest.h>

#include <random>

namespace dentsim {
namespace {

// Reference: classify each existing node by scanning its voxels directly.
void referenceCount(const BrickVolume& v, uint32_t x0, uint32_t y0, uint32_t z0, uint32_t size, size_t depth,
                    std::vector<OctreeLevelCounts>& levels) {
  bool any_solid = false, any_empty = false;
  for (uint32_t z = z0; z < z0 + size; ++z)
    for (uint32_t y = y0; y < y0 + size; ++y)
      for (uint32_t x = x0; x < x0 + size; ++x) (voxelSolid(v.voxel(x, y, z)) ? any_solid : any_empty) = true;
  if (!any_solid) { ++levels[depth].white; return; }
  if (!any_empty) { ++levels[depth].black; return; }
  ++levels[depth].mix;
  const uint32_t h = size / 2;
  for (uint32_t c = 0; c < 8; ++c)
    referenceCount(v, x0 + (c & 1) * h, y0 + ((c >> 1) & 1) * h, z0 + (c >> 2) * h, h, depth + 1, levels);
}

void expectLevels(const OctreeCounts& got, const std::vector<OctreeLevelCounts>& want) {
  ASSERT_EQ(got.levels.size(), want.size());
  for (size_t d = 0; d < want.size(); ++d) {
    EXPECT_EQ(got.levels[d].black, want[d].black) << "level " << d;
    EXPECT_EQ(got.levels[d].white, want[d].white) << "level " << d;
    EXPECT_EQ(got.levels[d].mix, want[d].mix) << "level " << d;
  }
}

TEST(OctreeStats, EmptyAndFullGridsAreOneNode) {
  BrickVolume empty(4);
  expectLevels(octreeNodeCounts(empty), {{0, 1, 0}, {}, {}, {}, {}});
  BrickVolume full(4);
  for (uint32_t b = 0; b < 8; ++b) full.setBrickUniform({b & 1, (b >> 1) & 1, b >> 2}, makeVoxel(Material::Dentin));
  expectLevels(octreeNodeCounts(full), {{1, 0, 0}, {}, {}, {}, {}});
}

TEST(OctreeStats, OneVoxelInA16CubeMakesAChainOfMixNodes) {
  // Root mix; at each of the 4 levels below, 8 children of which 1 is mix (or the black voxel)
  // and 7 white: 1 + 4 x 8 = 33 nodes.
  BrickVolume v(4);
  v.setVoxel(9, 2, 13, makeVoxel(Material::Enamel));
  const OctreeCounts c = octreeNodeCounts(v);
  expectLevels(c, {{0, 0, 1}, {0, 7, 1}, {0, 7, 1}, {0, 7, 1}, {1, 7, 0}});
  EXPECT_EQ(c.nodes(), 33u);
}

TEST(OctreeStats, HalfFilledGridSplitsOnce) {
  BrickVolume v(5);
  for (uint32_t z = 0; z < 32; ++z)
    for (uint32_t y = 0; y < 32; ++y)
      for (uint32_t x = 0; x < 16; ++x) v.setVoxel(x, y, z, makeVoxel(Material::Enamel));
  expectLevels(octreeNodeCounts(v), {{0, 0, 1}, {4, 4, 0}, {}, {}, {}, {}});
}

TEST(OctreeStats, SolidMeansAtLeastHalfFull) {
  BrickVolume v(3);
  v.setVoxel(0, 0, 0, makeVoxel(Material::Enamel, 15));
  EXPECT_EQ(octreeNodeCounts(v).levels[0].white, 1u);
  v.setVoxel(0, 0, 0, makeVoxel(Material::Enamel, 16));
  EXPECT_EQ(octreeNodeCounts(v).levels[0].mix, 1u);
}

TEST(OctreeStats, MatchesBruteForceOnRandomBlobs) {
  for (int level : {3, 5, 7, 8}) {
    BrickVolume v(level);
    std::mt19937 rng{static_cast<uint32_t>(level)};
    const uint32_t n = v.dim();
    // Random boxes give uniform bricks, dense bricks and whole solid chunks.
    for (int box = 0; box < 12; ++box) {
      const uint32_t x0 = rng() % n, y0 = rng() % n, z0 = rng() % n;
      const uint32_t s = 1 + rng() % (n / 2);
      const Voxel val = box % 4 == 3 ? Voxel(0) : makeVoxel(Material(1 + rng() % 4), 1 + rng() % 31);
      for (uint32_t z = z0; z < std::min(n, z0 + s); ++z)
        for (uint32_t y = y0; y < std::min(n, y0 + s); ++y)
          for (uint32_t x = x0; x < std::min(n, x0 + s); ++x) v.setVoxel(x, y, z, val);
    }
    v.compact();
    std::vector<OctreeLevelCounts> want(size_t(level) + 1);
    referenceCount(v, 0, 0, 0, n, 0, want);
    SCOPED_TRACE("level " + std::to_string(level));
    expectLevels(octreeNodeCounts(v), want);
  }
}

TEST(OctreeStats, ARodThroughALevel13GridCountsByHand) {
  // One row of full voxels along x through a level-13 grid (8192^3 voxels, 2^30 bricks). Each mix
  // node has 8 children, 2 along the rod and 6 beside it: at levels 1..12 the rod's 2^d nodes are
  // mix and 3 * 2^d are white; at level 13 the rod is 2^13 black voxels beside 3 * 2^13 white ones.
  // Counting chunk by chunk touches the rod's 128 chunks, not the grid (the whole grid's brick
  // states would take 1 GiB).
  BrickVolume v(13);
  for (uint32_t x = 0; x < v.dim(); ++x) v.setVoxel(x, 4000, 77, makeVoxel(Material::Dentin, DS_FILL_FULL));
  v.compact();
  const OctreeCounts c = octreeNodeCounts(v);
  ASSERT_EQ(c.levels.size(), 14u);
  EXPECT_EQ(c.levels[0].mix, 1u);
  for (size_t d = 1; d <= 12; ++d) {
    SCOPED_TRACE("level " + std::to_string(d));
    EXPECT_EQ(c.levels[d].mix, uint64_t{1} << d);
    EXPECT_EQ(c.levels[d].white, uint64_t{3} << d);
    EXPECT_EQ(c.levels[d].black, 0u);
  }
  EXPECT_EQ(c.levels[13].black, uint64_t{1} << 13);
  EXPECT_EQ(c.levels[13].white, uint64_t{3} << 13);
  EXPECT_EQ(c.levels[13].mix, 0u);
}

}  // namespace
}  // namespace dentsim
