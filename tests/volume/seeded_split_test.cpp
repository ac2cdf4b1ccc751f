// Tests of src/volume/seeded_split.cpp: two cubes joined by a thin rod part, or merge, exactly where the depth rule says.
#include "volume/seeded_split.h"

#include <gtest/gtest.h>

namespace dentsim {
namespace {

// A dumbbell in a 17 x 9 x 9 grid of 0.125 mm voxels (exact in binary, so depths are exact):
// cube A (x 1..7, y and z 1..7, 343 voxels), a 1-voxel rod (x 8..10 at y = z = 4) and cube B
// (x 11..15, y and z 2..6, 125 voxels). Depths (distance to the nearest outside centre): A's centre
// 4 voxels = 0.5 mm, B's centre 3 voxels = 0.375 mm, the rod 1 voxel = 0.125 mm. So B's peak
// stands 0.25 mm above the rod where the two regions meet.
struct Dumbbell {
  std::array<int32_t, 3> d{17, 9, 9};
  std::array<double, 3> pitch{0.125, 0.125, 0.125};
  std::vector<uint8_t> grid = std::vector<uint8_t>(17 * 9 * 9, 0);
  static size_t at(int x, int y, int z) { return size_t(x + 17 * (y + 9 * z)); }
  Dumbbell() {
    for (int z = 0; z < 9; ++z)
      for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 17; ++x) grid[at(x, y, z)] = inA(x, y, z) || inB(x, y, z) || inRod(x, y, z);
  }
  static bool inA(int x, int y, int z) { return x >= 1 && x <= 7 && y >= 1 && y <= 7 && z >= 1 && z <= 7; }
  static bool inB(int x, int y, int z) { return x >= 11 && x <= 15 && y >= 2 && y <= 6 && z >= 2 && z <= 6; }
  static bool inRod(int x, int y, int z) { return x >= 8 && x <= 10 && y == 4 && z == 4; }
  // Kept voxels of A and of B.
  static std::array<int, 2> kept(const std::vector<uint8_t>& g) {
    std::array<int, 2> n{0, 0};
    for (int z = 0; z < 9; ++z)
      for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 17; ++x) {
          if (!g[at(x, y, z)]) continue;
          if (inA(x, y, z)) ++n[0];
          if (inB(x, y, z)) ++n[1];
        }
    return n;
  }
};

TEST(SeededSplit, ALowerPeakExactlyHAboveTheJoinStaysApart) {
  // h = 0.25 mm: B's peak is not less than h above the join, so B is cut from the seed's cube A.
  Dumbbell b;
  std::vector<uint8_t> g = b.grid;
  ASSERT_TRUE(keepSeededPart(g, b.d, b.pitch, Dumbbell::at(4, 4, 4), 0.25, 0.0));
  EXPECT_EQ(Dumbbell::kept(g), (std::array<int, 2>{343, 0}));
  // Seeded in B instead, B is kept and A cut.
  g = b.grid;
  ASSERT_TRUE(keepSeededPart(g, b.d, b.pitch, Dumbbell::at(13, 4, 4), 0.25, 0.0));
  EXPECT_EQ(Dumbbell::kept(g), (std::array<int, 2>{0, 125}));
}

TEST(SeededSplit, ALowerPeakLessThanHAboveTheJoinMerges) {
  // h one depth step (0.125 / 16 mm) more than B's 0.25 mm: B joins A, and all 471 voxels stay.
  Dumbbell b;
  std::vector<uint8_t> g = b.grid;
  ASSERT_TRUE(keepSeededPart(g, b.d, b.pitch, Dumbbell::at(13, 4, 4), 0.25 + 0.125 / 16, 0.0));
  EXPECT_EQ(Dumbbell::kept(g), (std::array<int, 2>{343, 125}));
  EXPECT_EQ(g, b.grid);
}

TEST(SeededSplit, TheFilledPulpShapesTheCutButNeverEntersTheResult) {
  // A hollow cube in a 13^3 grid of 0.125 mm voxels: walls x, y, z 1..11, one voxel thick, round a
  // 9^3 cavity, with a one-voxel opening (a foramen) in the -z wall. Every wall voxel is one voxel
  // deep, so without the fill the walls are all one flat part; with it (sealed by one voxel) the
  // cube is solid for the transform. Either way the seed keeps every wall voxel, and the cavity,
  // filled only for the transform, stays 0.
  const std::array<int32_t, 3> d{13, 13, 13};
  std::vector<uint8_t> grid(13 * 13 * 13, 0);
  const auto at = [](int x, int y, int z) { return size_t(x + 13 * (y + 13 * z)); };
  for (int z = 1; z <= 11; ++z)
    for (int y = 1; y <= 11; ++y)
      for (int x = 1; x <= 11; ++x) grid[at(x, y, z)] = x == 1 || x == 11 || y == 1 || y == 11 || z == 1 || z == 11;
  grid[at(6, 6, 1)] = 0;
  for (const double seal : {0.0, 0.125}) {
    std::vector<uint8_t> g = grid;
    ASSERT_TRUE(keepSeededPart(g, d, {0.125, 0.125, 0.125}, at(1, 1, 1), 0.25, seal));
    EXPECT_EQ(g, grid) << "seal " << seal;
  }
}

TEST(SeededSplit, ACancelStopsTheSplit) {
  struct Refuse : Interrupter {
    bool progress(double) override { return false; }
  } refuse;
  Dumbbell b;
  std::vector<uint8_t> g = b.grid;
  EXPECT_FALSE(keepSeededPart(g, b.d, b.pitch, Dumbbell::at(4, 4, 4), 0.25, 0.0, refuse));
}

}  // namespace
}  // namespace dentsim
