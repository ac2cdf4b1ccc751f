// Tests for core/percentile.h: nearest rank on lists and histograms, against ranks counted by hand.
#include "core/percentile.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace dentsim {
namespace {

TEST(PercentileTest, RankIsCeilingOfShareOfCount) {
  // 10 samples: p50 covers 5 of them, p95 needs 9.5 -> the 10th, p0 still the 1st.
  EXPECT_EQ(percentileRank(50.0, 10), 5u);
  EXPECT_EQ(percentileRank(95.0, 10), 10u);
  EXPECT_EQ(percentileRank(90.0, 10), 9u);
  EXPECT_EQ(percentileRank(0.0, 10), 1u);
  EXPECT_EQ(percentileRank(100.0, 10), 10u);
  // 20 samples: p95 is exactly 19 of them, so the 19th, not the 20th.
  EXPECT_EQ(percentileRank(95.0, 20), 19u);
  EXPECT_EQ(percentileRank(50.0, 1), 1u);
}

TEST(PercentileTest, ListIsOneOfTheSamples) {
  // Sorted {1,2,3,4,5}: p50 is rank ceil(2.5) = 3 -> 3.
  EXPECT_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 50.0), 3.0);
  EXPECT_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 100.0), 5.0);
  EXPECT_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 0.0), 1.0);
  // An even count takes the lower middle, no mean: {1,2,3,4} p50 = rank 2 -> 2.
  EXPECT_EQ(percentile({4.0, 3.0, 2.0, 1.0}, 50.0), 2.0);
  // 1..20: p95 is rank 19 -> 19.
  std::vector<double> v;
  for (int i = 20; i >= 1; --i) v.push_back(i);
  EXPECT_EQ(percentile(v, 95.0), 19.0);
  const std::vector<double> sorted{1.0, 2.0, 3.0, 4.0};
  EXPECT_EQ(percentileSorted(sorted, 75.0), 3.0);  // rank 3
}

TEST(PercentileTest, HistogramFollowsTheSameRule) {
  // Bins hold 2, 0, 3, 5 samples (10 in all): ranks 1-2 in bin 0, 3-5 in bin 2, 6-10 in bin 3.
  const std::vector<uint32_t> counts{2, 0, 3, 5};
  EXPECT_EQ(percentileBin<uint32_t>(counts, 0.0), 0u);    // rank 1
  EXPECT_EQ(percentileBin<uint32_t>(counts, 20.0), 0u);   // rank 2
  EXPECT_EQ(percentileBin<uint32_t>(counts, 21.0), 2u);   // rank 3 (ceil 2.1)
  EXPECT_EQ(percentileBin<uint32_t>(counts, 50.0), 2u);   // rank 5
  EXPECT_EQ(percentileBin<uint32_t>(counts, 51.0), 3u);   // rank 6
  EXPECT_EQ(percentileBin<uint32_t>(counts, 100.0), 3u);  // rank 10
  // The list those bins stand for (bin index as value) gives the same answers.
  const std::vector<double> samples{0, 0, 2, 2, 2, 3, 3, 3, 3, 3};
  for (double p : {0.0, 10.0, 20.0, 21.0, 50.0, 51.0, 90.0, 100.0})
    EXPECT_EQ(double(percentileBin<uint32_t>(counts, p)), percentile(samples, p)) << "p" << p;
}

}  // namespace
}  // namespace dentsim
