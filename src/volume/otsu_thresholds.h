// Automatic grey-value thresholds: a histogram robust to a few outliers, and exact multi-level Otsu on it.
//
// Entry points:
//   robustHistogram(for_each)  256 bins over the 0.1 .. 99.9 percentile range of the values
//   otsuCuts(counts, classes)  the exact multi-level Otsu cuts, as bin indices
//   otsuThresholds(h, classes) the same cuts as grey values of a GreyHistogram
//
// The range rule: a scan holds a few metal or dead voxels far outside the tissues' values, and bins
// spread over the full range would leave the tissues a handful of bins. So the bins span the 0.1 to
// 99.9 percentiles (core's nearest-rank rule, read on a 65536-bin first pass), and values outside
// fall into the end bins.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace dentsim {

// A histogram of grey values [image unit: HU or raw].
struct GreyHistogram {
  double lo = 0, width = 1;   // lower edge of bin 0 and the bin width [image unit]
  std::vector<double> count;  // values per bin (kOtsuBins)
  double total = 0;           // finite values counted; 0: none
  double edge(size_t b) const { return lo + double(b) * width; }
  double centre(size_t b) const { return lo + (double(b) + 0.5) * width; }
};

constexpr size_t kOtsuBins = 256;         // an exact Otsu search over them is O(classes x bins^2)
constexpr size_t kRangeFineBins = 65536;  // the first pass's bins, from which the percentiles are read

namespace internal {
// The GreyHistogram of a fine histogram of kRangeFineBins bins of `fine_width` from `vmin`.
GreyHistogram robustFromFine(const std::vector<double>& fine, double vmin, double fine_width);
}  // namespace internal

// The histogram of the finite values that for_each(f) hands to f (as float), over their 0.1 .. 99.9
// percentile range. for_each is called twice (the range, then a fine histogram), and must hand the
// same values both times. No finite value: total 0 and every count 0.
template <class ForEach>
GreyHistogram robustHistogram(ForEach&& for_each) {
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for_each([&](float v) {
    if (!std::isfinite(v)) return;
    vmin = std::min(vmin, double(v));
    vmax = std::max(vmax, double(v));
  });
  if (!(vmin <= vmax)) {
    GreyHistogram none;
    none.count.assign(kOtsuBins, 0.0);
    return none;
  }
  const double fine_width = vmax > vmin ? (vmax - vmin) / double(kRangeFineBins) : 1.0;
  std::vector<double> fine(kRangeFineBins, 0.0);
  for_each([&](float v) {
    if (!std::isfinite(v)) return;
    const double b = std::floor((double(v) - vmin) / fine_width);
    fine[size_t(std::clamp(b, 0.0, double(kRangeFineBins - 1)))] += 1.0;
  });
  return internal::robustFromFine(fine, vmin, fine_width);
}

// Exact multi-level Otsu over a histogram: the cuts b_1 < ... < b_{classes-1} (class j holds bins
// [b_j, b_{j+1}), b_0 = 0, b_classes = counts.size(), each at least one bin) that maximise the
// between-class variance. 2 <= classes <= counts.size(). Dynamic programming over prefix sums,
// O(classes x bins^2).
std::vector<size_t> otsuCuts(const std::vector<double>& counts, int classes);

// Otsu's cuts as grey values: the lower edge of each upper class's first bin, ascending.
std::vector<double> otsuThresholds(const GreyHistogram& h, int classes);

}  // namespace dentsim
