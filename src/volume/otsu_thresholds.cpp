// The robust histogram's range and bins, and exact multi-level Otsu.
#include "volume/otsu_thresholds.h"

#include "core/percentile.h"

#include <cassert>
#include <span>

namespace dentsim {

namespace internal {

GreyHistogram robustFromFine(const std::vector<double>& fine, double vmin, double fine_width) {
  assert(fine.size() == kRangeFineBins);
  GreyHistogram h;
  h.count.assign(kOtsuBins, 0.0);
  double total = 0;
  for (double c : fine) total += c;
  if (total == 0) return h;
  const std::span<const double> counts(fine);
  const size_t b_lo = percentileBin(counts, 0.1), b_hi = percentileBin(counts, 99.9);
  h.lo = vmin + double(b_lo) * fine_width;
  h.width = double(b_hi + 1 - b_lo) * fine_width / double(kOtsuBins);
  // Each fine bin goes whole into the bin holding its centre; the ends take what lies beyond.
  for (size_t b = 0; b < kRangeFineBins; ++b) {
    if (fine[b] == 0) continue;
    const double c = vmin + (double(b) + 0.5) * fine_width;
    const double t = std::floor((c - h.lo) / h.width);
    h.count[size_t(std::clamp(t, 0.0, double(kOtsuBins - 1)))] += fine[b];
  }
  h.total = total;
  return h;
}

}  // namespace internal

// best[j][b] is the largest sum of S^2/P over j classes covering bins [0, b) (P a class's count, S
// its sum of bin indices); maximising it maximises the between-class variance, since the total
// mean is fixed. Every class holds at least one bin.
std::vector<size_t> otsuCuts(const std::vector<double>& counts, int classes) {
  const size_t n = counts.size();
  const size_t k = size_t(classes);
  assert(classes >= 2 && n >= k);
  std::vector<double> p(n + 1, 0.0), s(n + 1, 0.0);
  for (size_t b = 0; b < n; ++b) {
    p[b + 1] = p[b] + counts[b];
    s[b + 1] = s[b] + counts[b] * double(b);
  }
  auto term = [&](size_t a, size_t b) {
    const double w = p[b] - p[a];
    return w > 0 ? (s[b] - s[a]) * (s[b] - s[a]) / w : 0.0;
  };
  const double none = -std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> best(k + 1, std::vector<double>(n + 1, none));
  std::vector<std::vector<size_t>> from(k + 1, std::vector<size_t>(n + 1, 0));
  for (size_t b = 1; b <= n; ++b) best[1][b] = term(0, b);
  for (size_t j = 2; j <= k; ++j)
    for (size_t b = j; b <= n; ++b)
      for (size_t a = j - 1; a < b; ++a) {
        const double v = best[j - 1][a] + term(a, b);
        if (v > best[j][b]) {
          best[j][b] = v;
          from[j][b] = a;
        }
      }
  std::vector<size_t> cuts(k - 1);
  size_t b = n;
  for (size_t j = k; j >= 2; --j) {
    b = from[j][b];
    cuts[j - 2] = b;
  }
  return cuts;
}

std::vector<double> otsuThresholds(const GreyHistogram& h, int classes) {
  std::vector<double> out;
  for (size_t b : otsuCuts(h.count, classes)) out.push_back(h.edge(b));
  return out;
}

}  // namespace dentsim
