// Tests of src/volume/distance_transform.cpp: the exact squared distance against a hand count and against brute force on small anisotropic grids.
#include "volume/distance_transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dentsim {
namespace {

TEST(DistanceTransform, OneVoxelInsideIsOneSmallestPitchDeep) {
  // The centre of a 3^3 grid, alone inside: its nearest outside centre is one step along the axis
  // of the smallest pitch, 0.3 mm, so 0.09 mm^2; every other voxel is outside (0).
  std::vector<uint8_t> inside(27, 0);
  inside[13] = 1;
  const std::vector<float> d2 = squaredDistanceToOutside(inside, {3, 3, 3}, {0.5, 0.3, 0.7});
  EXPECT_FLOAT_EQ(d2[13], 0.09f);
  for (size_t i = 0; i < 27; ++i) {
    if (i == 13) continue;
    EXPECT_EQ(d2[i], 0.0f) << i;
  }
}

TEST(DistanceTransform, AllInsideIsInfinitelyDeep) {
  // Beyond the grid is no outside: with no 0 voxel there is nothing to measure to.
  const std::vector<float> d2 = squaredDistanceToOutside(std::vector<uint8_t>(24, 1), {4, 3, 2}, {1, 1, 1});
  for (float v : d2) EXPECT_EQ(v, std::numeric_limits<float>::infinity());
}

TEST(DistanceTransform, EqualsBruteForceOnRandomAnisotropicGrids) {
  std::mt19937 rng(3);
  const std::array<int32_t, 3> d{8, 6, 7};
  const std::array<double, 3> pitch{0.034, 0.05, 0.1};
  const size_t n = 8 * 6 * 7;
  for (int density : {2, 6, 30}) {
    // Mostly inside: one voxel in `density` is outside (at least one, so every depth is finite).
    std::vector<uint8_t> inside(n);
    for (uint8_t& v : inside) v = rng() % uint32_t(density) == 0 ? 0 : 1;
    inside[rng() % n] = 0;
    const std::vector<float> d2 = squaredDistanceToOutside(inside, d, pitch);
    for (size_t p = 0; p < n; ++p) {
      const int64_t px = int64_t(p % 8), py = int64_t(p / 8 % 6), pz = int64_t(p / 48);
      double best = std::numeric_limits<double>::infinity();
      for (size_t q = 0; q < n; ++q) {
        if (inside[q]) continue;
        const double dx = double(int64_t(q % 8) - px) * pitch[0], dy = double(int64_t(q / 8 % 6) - py) * pitch[1],
                     dz = double(int64_t(q / 48) - pz) * pitch[2];
        best = std::min(best, dx * dx + dy * dy + dz * dz);
      }
      // The result is float; the brute force's double differs by float rounding, applied after each axis.
      EXPECT_NEAR(d2[p], best, 1e-6 * best + 1e-12) << "density " << density << ", voxel " << p;
    }
  }
}

}  // namespace
}  // namespace dentsim
