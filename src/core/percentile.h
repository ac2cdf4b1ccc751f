// The one percentile rule (nearest rank) for every statistic dentsim reports, on a sample list or a histogram.
//
// Entry points:
//   percentileRank(p, n)        the 1-based rank of the p-th percentile among n samples
//   percentileSorted(sorted, p) the p-th percentile of an ascending list
//   percentile(values, p)       the same on a list in any order (sorts a copy)
//   percentileBin(counts, p)    the bin that holds the p-th percentile of a histogram
//
// Nearest rank: the p-th percentile is the smallest sample with at least p% of the samples at or
// below it, rank ceil(p/100 * n), and at least the first. It is always one of the samples (no
// interpolation), so p50 of {1, 2, 3, 4} is 2, p100 is the maximum and p0 the minimum. A
// histogram applies the same rule to its counts: p50 of a step-time histogram and p50 of the same
// steps kept as a list fall in the same bin.
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dentsim {

// p in [0, 100], n >= 1; the result is in [1, n].
inline size_t percentileRank(double p, size_t n) {
  assert(n > 0 && p >= 0.0 && p <= 100.0);
  const auto rank = size_t(std::ceil(p / 100.0 * double(n)));
  return std::clamp<size_t>(rank, 1, n);
}

// `sorted` ascending and non-empty.
inline double percentileSorted(std::span<const double> sorted, double p) {
  assert(!sorted.empty() && std::is_sorted(sorted.begin(), sorted.end()));
  return sorted[percentileRank(p, sorted.size()) - 1];
}

// `values` non-empty, in any order.
inline double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return percentileSorted(values, p);
}

// `counts[i]` samples fell in bin i (bins ascending); at least one sample in all. The caller maps
// the bin to a value (an edge or a centre) and says which in what it reports.
template <class Count>
size_t percentileBin(std::span<const Count> counts, double p) {
  uint64_t total = 0;
  for (Count c : counts) total += uint64_t(c);
  assert(total > 0);
  const uint64_t rank = percentileRank(p, size_t(total));
  uint64_t seen = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    seen += uint64_t(counts[i]);
    if (seen >= rank) return i;
  }
  return counts.size() - 1;  // unreachable: seen ends at total >= rank
}

}  // namespace dentsim
