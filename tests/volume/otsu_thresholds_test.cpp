// Tests of src/volume/otsu_thresholds.cpp: the robust histogram's range and Otsu's cuts on synthetic bi- and tri-modal data with analytic answers.
#include "volume/otsu_thresholds.h"

#include <gtest/gtest.h>

#include <vector>

namespace dentsim {
namespace {

// A for_each over a fixed list, as robustHistogram takes it.
auto over(const std::vector<float>& values) {
  return [&values](auto&& f) {
    for (float v : values) f(v);
  };
}

TEST(OtsuThresholds, UniformValuesSplitIntoEqualThirdsAndHalves) {
  // Uniform values on [0, 1000): the between-class variance of k classes is largest for k equal
  // widths (two classes: w (1 - w) / 4 peaks at w = 1/2), so 2-class Otsu cuts at 500 and 3-class
  // at 333.3 and 666.7. The histogram's bins are about 3.9 wide; a cut lies within one of them.
  std::vector<float> values;
  for (int i = 0; i < 100000; ++i) values.push_back(float(i) * 0.01f);
  const GreyHistogram h = robustHistogram(over(values));
  ASSERT_EQ(h.total, 100000.0);
  const std::vector<double> two = otsuThresholds(h, 2);
  ASSERT_EQ(two.size(), 1u);
  EXPECT_NEAR(two[0], 500.0, h.width);
  const std::vector<double> three = otsuThresholds(h, 3);
  ASSERT_EQ(three.size(), 2u);
  EXPECT_NEAR(three[0], 1000.0 / 3.0, h.width);
  EXPECT_NEAR(three[1], 2000.0 / 3.0, h.width);
}

TEST(OtsuThresholds, TriModalTissuesAreCutInTheirGaps) {
  // Air -1000, dentin 1700, enamel 2900 HU (make-scan's values), each spread +-100 HU evenly: any
  // cut in a gap separates the classes exactly, and 3-class Otsu must find one in each gap.
  std::vector<float> values;
  auto mode = [&](float centre, int count) {
    for (int i = 0; i < count; ++i) values.push_back(centre - 100.0f + 200.0f * float(i) / float(count - 1));
  };
  mode(-1000.0f, 60000);
  mode(1700.0f, 30000);
  mode(2900.0f, 10000);
  const std::vector<double> cuts = otsuThresholds(robustHistogram(over(values)), 3);
  ASSERT_EQ(cuts.size(), 2u);
  EXPECT_GT(cuts[0], -900.0);
  EXPECT_LE(cuts[0], 1600.0);
  EXPECT_GT(cuts[1], 1800.0);
  EXPECT_LE(cuts[1], 2800.0);
}

TEST(OtsuThresholds, OutliersFallIntoTheEndBinsAndDoNotStretchThem) {
  // 9990 values evenly on [100, 200] and 5 outliers at each of -5000 and +5000 HU (metal, dead
  // pixels). 0.1 % of 10000 is 10 values: the range's nearest-rank percentiles (rank 10 and 9990)
  // are both in the cluster, so the bins span [100, 200] to within a fine bin (10000 / 65536 HU),
  // not [-5000, 5000], and the outliers land in bins 0 and 255.
  std::vector<float> values;
  for (int i = 0; i < 9990; ++i) values.push_back(100.0f + 100.0f * float(i) / 9989.0f);
  for (int i = 0; i < 5; ++i) {
    values.push_back(-5000.0f);
    values.push_back(5000.0f);
  }
  const GreyHistogram h = robustHistogram(over(values));
  const double fine = 10000.0 / 65536.0;
  EXPECT_EQ(h.total, 10000.0);
  EXPECT_NEAR(h.lo, 100.0, fine);
  EXPECT_NEAR(h.edge(kOtsuBins), 200.0, 2 * fine);
  EXPECT_GE(h.count[0], 5.0);
  EXPECT_GE(h.count[kOtsuBins - 1], 5.0);
  double sum = 0;
  for (double c : h.count) sum += c;
  EXPECT_EQ(sum, 10000.0);
}

TEST(OtsuThresholds, NoFiniteValueGivesAnEmptyHistogram) {
  const std::vector<float> values{std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
  const GreyHistogram h = robustHistogram(over(values));
  EXPECT_EQ(h.total, 0.0);
  EXPECT_EQ(h.count.size(), kOtsuBins);
}

TEST(OtsuThresholds, CutsAreExactOnAHandCountedHistogram) {
  // Spikes of 1, 1 and 2 at bins 0, 10 and 30: the sum of S^2/P is 10^2/2 + 60^2/2 = 1850 for
  // {0, 10} | {30}, against 0 + 70^2/3 = 1633.3 for {0} | {10, 30}; the first best cut is bin 11.
  std::vector<double> g(32, 0.0);
  g[0] = 1;
  g[10] = 1;
  g[30] = 2;
  EXPECT_EQ(otsuCuts(g, 2), (std::vector<size_t>{11}));
}

}  // namespace
}  // namespace dentsim
