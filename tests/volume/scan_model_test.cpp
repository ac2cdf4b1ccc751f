// The phantom scanner against hand-computed values: tissue values, the blur's mass and spread, the noise's spread and seed.
#include <gtest/gtest.h>

#include <cmath>

#include "volume/scan_model.h"

namespace dentsim {
namespace {

LabelImage cube(int n, Label fill_label) {
  LabelImage l;
  l.dims = {n, n, n};
  l.pitch_mm = {0.1, 0.1, 0.1};
  l.scanner_from_voxel = {0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 0.1, 0};
  l.labels.assign(size_t(l.voxelCount()), 0);
  l.labels[l.index(n / 2, n / 2, n / 2)] = fill_label;
  return l;
}

const std::map<int32_t, Material> kMap{{2, Material::Enamel}, {3, Material::Dentin}};

TEST(ScanModel, ValuesWithoutBlurOrNoise) {
  ScanModel m;
  m.blur_mm = 0;
  m.noise = 0;
  Result<GreyImage> g = simulateScan(cube(9, 3), kMap, m);
  ASSERT_TRUE(g) << g.message();
  EXPECT_EQ(g->values[g->index(4, 4, 4)], 1700.0f);
  EXPECT_EQ(g->values[g->index(0, 0, 0)], -1000.0f);
  EXPECT_EQ(g->unit, GreyUnit::Hounsfield);
  EXPECT_FALSE(simulateScan(cube(9, 7), kMap, m));  // label 7 is not mapped
}

// A lone voxel blurred keeps its excess over the background (the taps sum to 1), and the excess spreads
// as a Gaussian: along one axis, the next voxel holds exp(-1/2 (pitch/sigma)^2) of the centre's.
TEST(ScanModel, BlurKeepsMassAndSpreadsAsAGaussian) {
  ScanModel m;
  m.blur_mm = 0.1;  // one voxel
  m.noise = 0;
  Result<GreyImage> g = simulateScan(cube(21, 3), kMap, m);
  ASSERT_TRUE(g) << g.message();
  double excess = 0;
  for (float v : g->values) excess += double(v) + 1000.0;
  EXPECT_NEAR(excess, 2700.0, 0.5);
  const double centre = g->values[g->index(10, 10, 10)] + 1000.0, next = g->values[g->index(11, 10, 10)] + 1000.0;
  EXPECT_NEAR(next / centre, std::exp(-0.5), 1e-3);
  // --voxel-size rescales the pitch and the scanner matrix together.
  Result<GreyImage> coarse = simulateScan(cube(21, 3), kMap, m, 0.2);
  ASSERT_TRUE(coarse);
  EXPECT_EQ(coarse->pitch_mm[1], 0.2);
  EXPECT_EQ(coarse->scanner_from_voxel[5], 0.2);
}

TEST(ScanModel, NoiseHasItsSpreadAndFollowsTheSeed) {
  ScanModel m;
  m.blur_mm = 0;
  m.noise = 50;
  Result<GreyImage> a = simulateScan(cube(40, 0), kMap, m), b = simulateScan(cube(40, 0), kMap, m);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->values, b->values);
  double sum = 0, sq = 0;
  for (float v : a->values) {
    sum += v + 1000.0;
    sq += (v + 1000.0) * (v + 1000.0);
  }
  const double n = double(a->values.size()), mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 1.0);   // 64000 samples: the mean's own spread is 50/253 = 0.2
  EXPECT_NEAR(sd, 50.0, 1.0);
  m.seed = 2;
  Result<GreyImage> c = simulateScan(cube(40, 0), kMap, m);
  EXPECT_NE(a->values, c->values);
}

}  // namespace
}  // namespace dentsim
