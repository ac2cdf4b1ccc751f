// Tests of src/volume/voxel_grid_ops.cpp: indices, face neighbours, the border flood, the piece flood and the box dilation, against hand counts and brute force.
#include "volume/voxel_grid_ops.h"

#include <gtest/gtest.h>

#include <random>

namespace dentsim {
namespace {

TEST(VoxelGridOps, IndexAndCoordsRoundTripIFastest) {
  const std::array<int32_t, 3> d{4, 3, 2};
  // (1, 2, 1) is 1 + 4 * (2 + 3 * 1) = 21.
  EXPECT_EQ(voxelIndex({1, 2, 1}, d), 21u);
  for (uint64_t l = 0; l < 24; ++l) EXPECT_EQ(voxelIndex(voxelCoords(l, d), d), l);
}

TEST(VoxelGridOps, FaceNeighboursCountAndOrder) {
  const std::array<int32_t, 3> d{3, 3, 3};
  std::vector<uint64_t> seen;
  // The centre (1, 1, 1) = 13 has all six, in the order -i, +i, -j, +j, -k, +k.
  forEachFaceNeighbour(13, d, [&](uint64_t j) { seen.push_back(j); });
  EXPECT_EQ(seen, (std::vector<uint64_t>{12, 14, 10, 16, 4, 22}));
  // A corner has three, an edge voxel four, a face centre five.
  auto count = [&](uint64_t l) {
    int n = 0;
    forEachFaceNeighbour(l, d, [&](uint64_t) { ++n; });
    return n;
  };
  EXPECT_EQ(count(0), 3);
  EXPECT_EQ(count(1), 4);
  EXPECT_EQ(count(4), 5);
  // In a grid one voxel thick along k, the middle (1, 1, 0) has no k neighbours: four.
  int flat = 0;
  forEachFaceNeighbour(4, {3, 3, 1}, [&](uint64_t) { ++flat; });
  EXPECT_EQ(flat, 4);
}

TEST(VoxelGridOps, BorderFloodStopsAtAClosedShell) {
  // 5^3 empty grid with a closed shell (the 26 voxels around (2, 2, 2)): the flood takes the
  // 125 - 27 = 98 voxels outside the shell and never the one inside it.
  const std::array<int32_t, 3> d{5, 5, 5};
  std::vector<uint8_t> cells(125, 0);
  for (int64_t z = 1; z <= 3; ++z)
    for (int64_t y = 1; y <= 3; ++y)
      for (int64_t x = 1; x <= 3; ++x)
        if (!(x == 2 && y == 2 && z == 2)) cells[voxelIndex({x, y, z}, d)] = 1;
  std::deque<uint64_t> queue;
  uint64_t taken = 0;
  const bool done = floodFromBorder(
      d, queue,
      [&](uint64_t l) {
        if (cells[l] != 0) return false;
        cells[l] = 2;
        ++taken;
        return true;
      },
      [](double) { return true; });
  EXPECT_TRUE(done);
  EXPECT_EQ(taken, 98u);
  EXPECT_EQ(cells[voxelIndex({2, 2, 2}, d)], 0);
  // Open one face of the shell: the inside is reached too.
  for (uint8_t& c : cells) c = c == 2 ? 0 : c;
  cells[voxelIndex({2, 2, 1}, d)] = 0;
  taken = 0;
  floodFromBorder(
      d, queue,
      [&](uint64_t l) {
        if (cells[l] != 0) return false;
        cells[l] = 2;
        ++taken;
        return true;
      },
      [](double) { return true; });
  EXPECT_EQ(taken, 100u);
}

TEST(VoxelGridOps, BorderFloodStopsWhenProgressSaysSo) {
  // Progress is asked every 2^20 voxels taken: a 128^3 grid (2^21) asks once before the end.
  const std::array<int32_t, 3> d{128, 128, 128};
  std::vector<uint8_t> cells(size_t(1) << 21, 0);
  std::deque<uint64_t> queue;
  int asked = 0;
  const bool done = floodFromBorder(
      d, queue,
      [&](uint64_t l) {
        if (cells[l] != 0) return false;
        cells[l] = 1;
        return true;
      },
      [&](double fraction) {
        ++asked;
        EXPECT_DOUBLE_EQ(fraction, 0.5);
        return false;
      });
  EXPECT_FALSE(done);
  EXPECT_EQ(asked, 1);
  EXPECT_TRUE(queue.empty());
}

TEST(VoxelGridOps, FloodPieceCountsOnePieceAndItsBox) {
  // Two pieces in a 6 x 4 x 3 grid: an L of 4 voxels in the z = 0 layer and one voxel at (5, 3, 2).
  const std::array<int32_t, 3> d{6, 4, 3};
  VoxelBits mask(72), seen(72);
  for (auto c : std::vector<std::array<int64_t, 3>>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {5, 3, 2}})
    mask.set(voxelIndex(c, d));
  std::deque<uint64_t> queue;
  const VoxelPiece l = floodPiece(mask, seen, d, voxelIndex({1, 0, 0}, d), queue);
  EXPECT_EQ(l.voxels, 4u);
  EXPECT_EQ(l.box.lo, (std::array<int64_t, 3>{0, 0, 0}));
  EXPECT_EQ(l.box.hi, (std::array<int64_t, 3>{2, 1, 0}));
  EXPECT_TRUE(seen.test(voxelIndex({2, 1, 0}, d)));
  EXPECT_FALSE(seen.test(voxelIndex({5, 3, 2}, d)));
  const VoxelPiece one = floodPiece(mask, seen, d, voxelIndex({5, 3, 2}, d), queue);
  EXPECT_EQ(one.voxels, 1u);
  EXPECT_EQ(one.box.count(), 1u);
}

TEST(VoxelGridOps, DilateBitOfOneVoxelIsAClippedCube) {
  // One voxel at (1, 1, 1) of a 6^3 grid dilated by r = 2: the cube 0..3 on each axis (clipped
  // below at 0), 4^3 = 64 voxels.
  const std::array<int32_t, 3> d{6, 6, 6};
  std::vector<uint8_t> cells(216, 0);
  cells[voxelIndex({1, 1, 1}, d)] = 1;
  dilateBit(cells, d, 2, 1, 2);
  uint64_t set = 0;
  for (uint8_t c : cells) set += c;
  EXPECT_EQ(set, 64u);
  EXPECT_EQ(cells[voxelIndex({3, 3, 3}, d)], 1);
  EXPECT_EQ(cells[voxelIndex({4, 1, 1}, d)], 0);
}

TEST(VoxelGridOps, DilateBitEqualsBruteForceAndKeepsOtherBits) {
  std::mt19937 rng(7);
  const std::array<int32_t, 3> d{9, 7, 5};
  const size_t n = 9 * 7 * 5;
  for (int r = 0; r <= 3; ++r)
    for (int trial = 0; trial < 4; ++trial) {
      // Bit 0x10 is the plane dilated, 0x40 the scratch; 0x01 and 0x80 are other data to keep.
      std::vector<uint8_t> cells(n);
      for (uint8_t& c : cells) c = uint8_t((rng() % 13 == 0 ? 0x10 : 0) | (rng() & 0x81));
      std::vector<uint8_t> expect = cells;
      for (uint64_t l = 0; l < n; ++l) {
        const std::array<int64_t, 3> c = voxelCoords(l, d);
        bool any = false;
        for (uint64_t m = 0; m < n && !any; ++m) {
          const std::array<int64_t, 3> e = voxelCoords(m, d);
          any = (cells[m] & 0x10) && std::abs(e[0] - c[0]) <= r && std::abs(e[1] - c[1]) <= r &&
                std::abs(e[2] - c[2]) <= r;
        }
        expect[l] = uint8_t((expect[l] & ~0x10) | (any ? 0x10 : 0));
      }
      dilateBit(cells, d, r, 0x10, 0x40);
      EXPECT_EQ(cells, expect) << "r = " << r << ", trial " << trial;
    }
}

}  // namespace
}  // namespace dentsim
