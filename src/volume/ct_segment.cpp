// One tooth from grey values: ROI geometry, robust histograms and multi-level Otsu, the tooth's component and its cut from neighbours, tissue classes, partial volume, caries, islands.
//
// Contents
//   1. Presets
//   2. Small tools (bits, progress, boxes, scanner geometry, messages)
//   3. Histograms and multi-level Otsu
//   4. The hard mask and its pieces
//   5. The tooth: the largest piece, or the seeded piece cut from its neighbours (distance
//      transform, flood by dynamics)
//   6. Rules on the output box: outside, partial volume, edges, caries
//   7. Thresholds (presets, given, automatic, refined on the tooth), classes, the ROI box
//   8. segmentTooth
#include "volume/ct_segment.h"

#include "volume/brick_volume.h"
#include "volume/label_import.h"
#include "volume/tissue_table.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>

namespace dentsim {

// ---- 1. presets -----------------------------------------------------------------------------

// Published CT numbers: enamel 2000..3000 HU, dentin 1200..2000 HU, cortical bone 700..1900 HU,
// carious dentin a few hundred HU below sound dentin, soft tissue and pulp 20..80 HU. CBCT values on a
// HU-like scale run lower and wider (scatter, beam hardening), hence the lower cuts.
const std::vector<ToothSegmentPreset>& toothSegmentPresets() {
  static const std::vector<ToothSegmentPreset> presets = {
      {"ct-hu", "multi-slice CT in Hounsfield units: hard tissue from 1000 HU, enamel from 2100 HU, caries from 500 HU",
       GreyUnit::Hounsfield, 1000.0, 2100.0, 500.0},
      {"cbct-hu", "cone-beam CT exported on a HU-like scale: hard tissue from 700 HU, enamel from 1600 HU, caries from 350 HU",
       GreyUnit::Hounsfield, 700.0, 1600.0, 350.0},
  };
  return presets;
}

std::string toothSegmentPresetNames() {
  std::string out;
  for (const ToothSegmentPreset& p : toothSegmentPresets()) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out;
}

namespace {

// ---- 2. small tools -------------------------------------------------------------------------

// One bit a voxel: 18 MB for a 600 x 600 x 400 scan, where a byte would be 144 MB.
class Bits {
 public:
  explicit Bits(size_t n = 0) : words_((n + 63) / 64, 0) {}
  bool test(uint64_t i) const { return (words_[i >> 6] >> (i & 63)) & 1u; }
  void set(uint64_t i) { words_[i >> 6] |= uint64_t{1} << (i & 63); }

 private:
  std::vector<uint64_t> words_;
};

// Progress over consecutive steps: step k of the job covers [begin, end) of the bar.
struct Stage {
  Interrupter& interrupter;
  double begin = 0.0, end = 1.0;
  bool report(double fraction) const { return interrupter.progress(begin + (end - begin) * fraction); }
};

// Hands cleanSmallPieces' progress on into one step of this job and remembers a cancel, so the
// error can name the segmentation rather than an import.
class StageInterrupter : public Interrupter {
 public:
  explicit StageInterrupter(const Stage& stage) : stage_(stage) {}
  bool progress(double fraction) override {
    cancelled = cancelled || !stage_.report(fraction);
    return !cancelled;
  }
  bool cancelled = false;

 private:
  Stage stage_;
};

Error cancelled(const std::string& where) { return makeError(where, "segmentation cancelled"); }

// An inclusive box of voxel indices; local index x + nx * (y + ny * z) from its low corner.
struct Box {
  std::array<int64_t, 3> lo{0, 0, 0}, hi{-1, -1, -1};
  int64_t size(int a) const { return hi[size_t(a)] - lo[size_t(a)] + 1; }
  std::array<int32_t, 3> dims() const { return {int32_t(size(0)), int32_t(size(1)), int32_t(size(2))}; }
  uint64_t count() const { return uint64_t(size(0)) * uint64_t(size(1)) * uint64_t(size(2)); }
};

// Local (x, y, z) of a local index.
std::array<int64_t, 3> coordsOf(uint64_t l, const std::array<int32_t, 3>& d) {
  const uint64_t row = l / uint64_t(d[0]);
  return {int64_t(l - row * uint64_t(d[0])), int64_t(row % uint64_t(d[1])), int64_t(row / uint64_t(d[1]))};
}

// The local index of local (x, y, z).
uint64_t localIndex(const std::array<int64_t, 3>& c, const std::array<int32_t, 3>& d) {
  return uint64_t(c[0] + d[0] * (c[1] + int64_t{d[1]} * c[2]));
}

// Calls f(j) for each face neighbour j of local index l inside a grid of dims d.
template <class F>
void forEachFaceNeighbour(uint64_t l, const std::array<int32_t, 3>& d, F&& f) {
  const std::array<int64_t, 3> c = coordsOf(l, d);
  const uint64_t sy = uint64_t(d[0]), sz = uint64_t(d[0]) * uint64_t(d[1]);
  if (c[0] > 0) f(l - 1);
  if (c[0] + 1 < d[0]) f(l + 1);
  if (c[1] > 0) f(l - sy);
  if (c[1] + 1 < d[1]) f(l + sy);
  if (c[2] > 0) f(l - sz);
  if (c[2] + 1 < d[2]) f(l + sz);
}

// The inverse of a 3 x 4 affine map (rows r: m[4r..4r+2] linear, m[4r+3] offset); false when singular.
bool invertAffine(const std::array<double, 12>& m, std::array<double, 12>& inv) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  const double r[9] = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                       (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                       (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) inv[size_t(4 * row + col)] = r[3 * row + col];
    inv[size_t(4 * row + 3)] = -(r[3 * row] * m[3] + r[3 * row + 1] * m[7] + r[3 * row + 2] * m[11]);
  }
  return true;
}

std::array<double, 3> applyAffine(const std::array<double, 12>& m, const std::array<double, 3>& p) {
  std::array<double, 3> out{};
  for (size_t r = 0; r < 3; ++r) out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
  return out;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string mmPoint(const std::array<double, 3>& p) {
  return "(" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + ") mm";
}

// ---- 3. histograms and multi-level Otsu -----------------------------------------------------

constexpr size_t kBins = 256;         // Otsu's bins: an exact search over them is O(classes x bins^2)
constexpr size_t kFineBins = 65536;   // the first pass's bins, for the percentiles

struct Histogram {
  double lo = 0, width = 1;    // lower edge of bin 0 and bin width [image unit]
  std::vector<double> count;   // voxels per bin (kBins)
  double total = 0;
  double edge(size_t b) const { return lo + double(b) * width; }
  double centre(size_t b) const { return lo + (double(b) + 0.5) * width; }
};

// The histogram of the finite values for_each(f) hands to f, over the 0.1 .. 99.9 percentile range;
// values outside it fall into the end bins. Two passes: the range, then a fine histogram from which
// both the percentiles and the Otsu bins are read.
template <class ForEach>
Histogram robustHistogram(ForEach&& for_each) {
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for_each([&](float v) {
    if (!std::isfinite(v)) return;
    vmin = std::min(vmin, double(v));
    vmax = std::max(vmax, double(v));
  });
  Histogram h;
  h.count.assign(kBins, 0.0);
  if (!(vmin <= vmax)) return h;
  const double fine_width = vmax > vmin ? (vmax - vmin) / double(kFineBins) : 1.0;
  std::vector<double> fine(kFineBins, 0.0);
  for_each([&](float v) {
    if (!std::isfinite(v)) return;
    const double b = std::floor((double(v) - vmin) / fine_width);
    fine[size_t(std::clamp(b, 0.0, double(kFineBins - 1)))] += 1.0;
  });
  double total = 0;
  for (double c : fine) total += c;
  // Percentile bins: the first whose running count passes the fraction.
  auto percentileBin = [&](double fraction) {
    double run = 0;
    for (size_t b = 0; b < kFineBins; ++b) {
      run += fine[b];
      if (run > fraction * total) return b;
    }
    return kFineBins - 1;
  };
  const size_t b_lo = percentileBin(0.001), b_hi = percentileBin(0.999);
  h.lo = vmin + double(b_lo) * fine_width;
  h.width = double(b_hi + 1 - b_lo) * fine_width / double(kBins);
  for (size_t b = 0; b < kFineBins; ++b) {
    if (fine[b] == 0) continue;
    const double c = vmin + (double(b) + 0.5) * fine_width;
    const double t = std::floor((c - h.lo) / h.width);
    h.count[size_t(std::clamp(t, 0.0, double(kBins - 1)))] += fine[b];
  }
  h.total = total;
  return h;
}

}  // namespace

namespace internal {

// Dynamic programming over the prefix sums: best[j][b] is the largest sum of S^2/P over j classes
// covering bins [0, b); every class holds at least one bin. Exact, O(classes x bins^2).
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

}  // namespace internal

namespace {

// Otsu's cuts as grey values: the lower edge of each upper class's first bin.
std::vector<double> otsuThresholds(const Histogram& h, int classes) {
  std::vector<double> out;
  for (size_t b : internal::otsuCuts(h.count, classes)) out.push_back(h.edge(b));
  return out;
}

// ---- 4. the hard mask and its pieces --------------------------------------------------------

// The ROI as a view of the image: local index -> the image's value.
struct RoiView {
  const GreyImage& image;
  Box box;
  std::array<int32_t, 3> d;
  float value(uint64_t l) const {
    const std::array<int64_t, 3> c = coordsOf(l, d);
    return image.values[image.index(box.lo[0] + c[0], box.lo[1] + c[1], box.lo[2] + c[2])];
  }
  // Calls f(local index, value) over the ROI in memory order.
  template <class F>
  void forEach(F&& f) const {
    uint64_t l = 0;
    for (int64_t z = box.lo[2]; z <= box.hi[2]; ++z)
      for (int64_t y = box.lo[1]; y <= box.hi[1]; ++y) {
        const float* row = &image.values[image.index(box.lo[0], y, z)];
        for (int64_t x = 0; x < d[0]; ++x, ++l) f(l, row[x]);
      }
  }
};

// One 6-connected piece of `mask`: its voxel count and local bounding box.
struct Piece {
  uint64_t voxels = 0;
  Box box;
};

// Floods the piece of `mask` holding `start` (breadth first: the queue stays near the front's
// size), setting its voxels in `seen`.
Piece floodPiece(const Bits& mask, Bits& seen, const std::array<int32_t, 3>& d, uint64_t start,
                 std::deque<uint64_t>& queue) {
  Piece piece;
  piece.box.lo = {d[0], d[1], d[2]};
  piece.box.hi = {-1, -1, -1};
  seen.set(start);
  queue.push_back(start);
  while (!queue.empty()) {
    const uint64_t l = queue.front();
    queue.pop_front();
    ++piece.voxels;
    const std::array<int64_t, 3> c = coordsOf(l, d);
    for (size_t a = 0; a < 3; ++a) {
      piece.box.lo[a] = std::min(piece.box.lo[a], c[a]);
      piece.box.hi[a] = std::max(piece.box.hi[a], c[a]);
    }
    forEachFaceNeighbour(l, d, [&](uint64_t j) {
      if (mask.test(j) && !seen.test(j)) {
        seen.set(j);
        queue.push_back(j);
      }
    });
  }
  return piece;
}

// ---- 5. the tooth ---------------------------------------------------------------------------

// Squared distance along one line to the nearest site: d[p] = min_q ((p - q) s)^2 + f[q], f[q]
// infinite where q is no site (Felzenszwalb & Huttenlocher's lower envelope of parabolas).
void distanceLine(const std::vector<double>& f, std::vector<double>& d, size_t n, double s,
                  std::vector<size_t>& v, std::vector<double>& z) {
  const double inf = std::numeric_limits<double>::infinity();
  const double s2 = s * s;
  int64_t k = -1;
  for (size_t q = 0; q < n; ++q) {
    if (!(f[q] < inf)) continue;
    double cross = -inf;
    while (k >= 0) {
      const size_t r = v[size_t(k)];
      const double dq = double(q), dr = double(r);
      cross = ((f[q] + s2 * dq * dq) - (f[r] + s2 * dr * dr)) / (2.0 * s2 * (dq - dr));
      if (cross <= z[size_t(k)]) --k;
      else break;
    }
    ++k;
    v[size_t(k)] = q;
    z[size_t(k)] = k == 0 ? -inf : cross;
  }
  if (k < 0) {
    std::fill(d.begin(), d.begin() + int64_t(n), inf);
    return;
  }
  z[size_t(k) + 1] = inf;
  size_t j = 0;
  for (size_t p = 0; p < n; ++p) {
    while (z[j + 1] < double(p)) ++j;
    const double t = (double(p) - double(v[j])) * s;
    d[p] = t * t + f[v[j]];
  }
}

// Squared distance [mm^2] from each voxel of the box to the nearest voxel outside `inside`, exact,
// one axis after another (the transform is separable). Voxels beyond the box are no sites.
std::vector<float> distanceTransform(const std::vector<uint8_t>& inside, const std::array<int32_t, 3>& d,
                                     const std::array<double, 3>& pitch) {
  const float finf = std::numeric_limits<float>::infinity();
  std::vector<float> out(inside.size());
  for (size_t i = 0; i < inside.size(); ++i) out[i] = inside[i] ? finf : 0.0f;
  const size_t longest = size_t(std::max({d[0], d[1], d[2]}));
  std::vector<double> f(longest), g(longest), z(longest + 1);
  std::vector<size_t> v(longest);
  const size_t stride[3] = {1, size_t(d[0]), size_t(d[0]) * size_t(d[1])};
  for (size_t a = 0; a < 3; ++a) {
    const size_t n = size_t(d[a]);
    const size_t b1 = a == 0 ? 1 : 0, b2 = a == 2 ? 1 : 2;  // the two other axes
    for (int64_t u = 0; u < d[b2]; ++u)
      for (int64_t w = 0; w < d[b1]; ++w) {
        const size_t base = size_t(w) * stride[b1] + size_t(u) * stride[b2];
        for (size_t p = 0; p < n; ++p) f[p] = double(out[base + p * stride[a]]);
        distanceLine(f, g, n, pitch[a], v, z);
        for (size_t p = 0; p < n; ++p) out[base + p * stride[a]] = float(g[p]);
      }
  }
  return out;
}

// Union-find over flood regions, each with its peak distance step.
struct Regions {
  std::vector<uint32_t> parent{0};  // region 0 is "not yet flooded"
  std::vector<uint32_t> peak{0};
  uint32_t find(uint32_t r) {
    while (parent[r] != r) {
      parent[r] = parent[parent[r]];
      r = parent[r];
    }
    return r;
  }
};

// The voxels of the seeded piece that belong to the seed's tooth. `piece` is the seed's hard piece
// as a 0/1 grid over its bounding box (local dims d); returns the same grid with the cut-away voxels
// cleared. The flood visits voxels from the deepest (largest inscribed ball) outwards; a voxel
// touching no flooded region starts one at its depth (a peak), and where regions meet, each whose
// peak stands less than h above the meeting voxel joins the one with the highest peak.
Result<std::vector<uint8_t>> cutTooth(std::vector<uint8_t> piece, const std::array<int32_t, 3>& d,
                                      const std::array<double, 3>& pitch, uint64_t seed, double h_mm,
                                      const Stage& stage, const std::string& where) {
  const double step = std::min({pitch[0], pitch[1], pitch[2]}) / 16.0;  // distance step [mm]
  std::vector<uint16_t> depth(piece.size(), 0);
  {
    const std::vector<float> d2 = distanceTransform(piece, d, pitch);
    for (size_t i = 0; i < piece.size(); ++i)
      if (piece[i]) depth[i] = uint16_t(std::min(65535.0, std::floor(std::sqrt(double(d2[i])) / step)));
  }
  if (!stage.report(0.3)) return cancelled(where);

  // Counting sort of the piece's voxels by depth, deepest first (scan order within a step).
  std::vector<uint64_t> start(65537, 0);
  for (size_t i = 0; i < piece.size(); ++i)
    if (piece[i]) ++start[65535 - size_t(depth[i]) + 1];
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<uint32_t> order(start.back());
  {
    std::vector<uint64_t> next(start.begin(), start.end() - 1);
    for (size_t i = 0; i < piece.size(); ++i)
      if (piece[i]) order[next[65535 - size_t(depth[i])]++] = uint32_t(i);
  }

  const uint32_t h_steps = uint32_t(std::max(0.0, std::ceil(h_mm / step - 1e-9)));
  Regions regions;
  std::vector<uint32_t> region(piece.size(), 0);
  for (size_t n = 0; n < order.size(); ++n) {
    const uint32_t i = order[n];
    const uint32_t level = depth[i];
    uint32_t roots[6];
    int count = 0;
    forEachFaceNeighbour(i, d, [&](uint64_t j) {
      if (region[j] == 0) return;
      const uint32_t r = regions.find(region[j]);
      for (int t = 0; t < count; ++t)
        if (roots[t] == r) return;
      roots[count++] = r;
    });
    if (count == 0) {
      const uint32_t id = uint32_t(regions.parent.size());
      regions.parent.push_back(id);
      regions.peak.push_back(level);
      region[i] = id;
      continue;
    }
    uint32_t top = roots[0];
    for (int t = 1; t < count; ++t)
      if (regions.peak[roots[t]] > regions.peak[top]) top = roots[t];
    for (int t = 0; t < count; ++t)
      if (roots[t] != top && regions.peak[roots[t]] - level < h_steps) regions.parent[roots[t]] = top;
    region[i] = top;
    if ((n & 0xFFFFF) == 0xFFFFF && !stage.report(0.3 + 0.7 * double(n) / double(order.size())))
      return cancelled(where);
  }
  const uint32_t tooth = regions.find(region[seed]);
  for (size_t i = 0; i < piece.size(); ++i)
    if (piece[i] && regions.find(region[i]) != tooth) piece[i] = 0;
  if (!stage.report(1.0)) return cancelled(where);
  return piece;
}

// The 0/1 grid of `mask` over a local box of the ROI.
std::vector<uint8_t> gridOf(const Bits& mask, const std::array<int32_t, 3>& roi_d, const Box& sub) {
  std::vector<uint8_t> out(sub.count());
  size_t i = 0;
  for (int64_t z = sub.lo[2]; z <= sub.hi[2]; ++z)
    for (int64_t y = sub.lo[1]; y <= sub.hi[1]; ++y)
      for (int64_t x = sub.lo[0]; x <= sub.hi[0]; ++x, ++i)
        out[i] = mask.test(localIndex({x, y, z}, roi_d)) ? 1 : 0;
  return out;
}

// The tooth's voxels in the ROI and their bounding box (ROI-local).
struct ToothMask {
  Bits bits;
  Box box;
};

// The seed's hard piece cut at narrow joins (cutTooth), or without a seed the largest hard piece.
Result<ToothMask> findTooth(const RoiView& roi, const Bits& hard, std::optional<uint64_t> seed,
                            const std::array<double, 3>& pitch, const ToothSegmentOptions& options, const Stage& stage,
                            std::deque<uint64_t>& queue, ToothSegmentReport& rep) {
  const uint64_t n_roi = roi.box.count();
  ToothMask tooth{Bits(n_roi), Box{}};
  if (!seed) {
    Bits seen(n_roi);
    uint64_t best = 0, best_start = 0;
    for (uint64_t l = 0; l < n_roi; ++l) {
      if (!hard.test(l) || seen.test(l)) continue;
      const Piece p = floodPiece(hard, seen, roi.d, l, queue);
      if (p.voxels > best) {
        best = p.voxels;
        best_start = l;
      }
    }
    const Piece largest = floodPiece(hard, tooth.bits, roi.d, best_start, queue);
    tooth.box = largest.box;
    rep.hard_component_voxels = rep.tooth_voxels = largest.voxels;
    return tooth;
  }
  const Piece piece = floodPiece(hard, tooth.bits, roi.d, *seed, queue);
  rep.hard_component_voxels = piece.voxels;
  if (!stage.report(0.2)) return cancelled(options.where);
  // The flood order holds 32-bit indices into the piece's box.
  if (piece.box.count() > std::numeric_limits<uint32_t>::max())
    return makeError(options.where, "the seed's hard tissue spans " + std::to_string(piece.box.count()) +
                                        " voxels, more than the cut handles (2^32): set an ROI around the tooth");
  const std::array<int32_t, 3> pd = piece.box.dims();
  const std::array<int64_t, 3> sc = coordsOf(*seed, roi.d);
  const uint64_t seed_in_piece = localIndex({sc[0] - piece.box.lo[0], sc[1] - piece.box.lo[1], sc[2] - piece.box.lo[2]}, pd);
  Result<std::vector<uint8_t>> kept = cutTooth(gridOf(tooth.bits, roi.d, piece.box), pd, pitch, seed_in_piece,
                                               options.split_h_mm, Stage{stage.interrupter, stage.begin + 0.2 * (stage.end - stage.begin), stage.end}, options.where);
  if (!kept) return kept.error();
  tooth.bits = Bits(n_roi);
  tooth.box.lo = {roi.d[0], roi.d[1], roi.d[2]};
  size_t i = 0;
  for (int64_t z = piece.box.lo[2]; z <= piece.box.hi[2]; ++z)
    for (int64_t y = piece.box.lo[1]; y <= piece.box.hi[1]; ++y)
      for (int64_t x = piece.box.lo[0]; x <= piece.box.hi[0]; ++x, ++i) {
        if (!(*kept)[i]) continue;
        tooth.bits.set(localIndex({x, y, z}, roi.d));
        ++rep.tooth_voxels;
        const int64_t c[3] = {x, y, z};
        for (size_t a = 0; a < 3; ++a) {
          tooth.box.lo[a] = std::min(tooth.box.lo[a], c[a]);
          tooth.box.hi[a] = std::max(tooth.box.hi[a], c[a]);
        }
      }
  rep.neighbour_voxels_cut = piece.voxels - rep.tooth_voxels;
  return tooth;
}

// ---- 6. rules on the output box -------------------------------------------------------------

// One byte a voxel of the output box: the class in bits 0-1, then flag bits.
constexpr uint8_t kClassMask = 0x03;
constexpr uint8_t kCaries = 1, kDentin = 2, kEnamel = 3;  // 0: not tooth
constexpr uint8_t kNearEmpty = 1u << 2;    // within w of the outside
constexpr uint8_t kNearEnamel = 1u << 3;   // within w of enamel
constexpr uint8_t kNearHard = 1u << 4;     // within w of dentin or enamel
constexpr uint8_t kOutside = 1u << 5;      // empty and connected to the box's border through empty
constexpr uint8_t kScratchA = 1u << 6, kScratchB = 1u << 7;

inline uint8_t classOf(uint8_t cell) { return cell & kClassMask; }

// Sets bit `dst` on every cell within r cells (box distance) of a cell where pred(cell) holds, one
// axis at a time through the two scratch bits.
template <class Pred>
void dilateInto(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, int r, uint8_t dst, Pred&& pred) {
  for (uint8_t& c : cells) c = uint8_t((c & ~(kScratchA | kScratchB)) | (pred(c) ? kScratchA : 0));
  const int64_t stride[3] = {1, d[0], int64_t{d[0]} * d[1]};
  const uint8_t from[3] = {kScratchA, kScratchB, kScratchA};
  const uint8_t to[3] = {kScratchB, kScratchA, dst};
  for (size_t a = 0; a < 3; ++a) {
    size_t i = 0;
    for (int64_t z = 0; z < d[2]; ++z)
      for (int64_t y = 0; y < d[1]; ++y)
        for (int64_t x = 0; x < d[0]; ++x, ++i) {
          const int64_t c = a == 0 ? x : a == 1 ? y : z;
          const int64_t t0 = std::max<int64_t>(-r, -c), t1 = std::min<int64_t>(r, d[a] - 1 - c);
          bool any = false;
          for (int64_t t = t0; t <= t1 && !any; ++t) any = (cells[size_t(int64_t(i) + t * stride[a])] & from[a]) != 0;
          if (any) cells[i] |= to[a];
        }
    // The source bit is spent once read along this axis: clear it for its next use as a target.
    if (a < 2)
      for (uint8_t& c : cells) c = uint8_t(c & ~from[a]);
  }
  for (uint8_t& c : cells) c = uint8_t(c & ~(kScratchA | kScratchB));
}

// Sets kOutside on the empty cells reached from the box's border through empty cells (clearing it
// elsewhere first). The rest of the empty space is enclosed: the pulp, when its canal is closed
// within the box.
void markOutside(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, std::deque<uint64_t>& queue) {
  auto reach = [&](uint64_t o) {
    if (classOf(cells[o]) != 0 || (cells[o] & kOutside)) return;
    cells[o] |= kOutside;
    queue.push_back(o);
  };
  for (uint8_t& c : cells) c = uint8_t(c & ~kOutside);
  for (uint64_t o = 0; o < cells.size(); ++o) {
    const std::array<int64_t, 3> c = coordsOf(o, d);
    bool border = false;
    for (size_t a = 0; a < 3; ++a) border = border || c[a] == 0 || c[a] == d[a] - 1;
    if (border) reach(o);
  }
  while (!queue.empty()) {
    const uint64_t o = queue.front();
    queue.pop_front();
    forEachFaceNeighbour(o, d, reach);
  }
}

// Mean grey value of each class in the box (index 0: non-tooth voxels below the hard threshold).
struct ClassMeans {
  std::array<double, 4> mean{};
  double midpoint(uint8_t dark, uint8_t bright) const { return 0.5 * (mean[dark] + mean[bright]); }
};

// The output box's cells (one byte each: class and flags) over the image's grey values.
struct BoxCells {
  const GreyImage& image;
  std::array<int64_t, 3> lo;   // the image voxel of cell 0
  std::array<int32_t, 3> d;    // cells along i, j, k
  std::vector<uint8_t> cells;  // (d[0] * d[1] * d[2]), i fastest
  float value(uint64_t o) const {
    const std::array<int64_t, 3> c = coordsOf(o, d);
    return image.values[image.index(lo[0] + c[0], lo[1] + c[1], lo[2] + c[2])];
  }
};

// The partial-volume rule (see the header); decisions from the classes before any change, applied
// at once. Returns the voxels reassigned.
uint64_t applyPartialVolume(BoxCells& box, int w, bool caries, const ClassMeans& means, std::deque<uint64_t>& queue) {
  std::vector<uint8_t>& cells = box.cells;
  // Only the outside counts as the darker class: enamel never faces the pulp, and noise specks
  // of enamel near the pulp wall must not pull dentin into enamel.
  markOutside(cells, box.d, queue);
  dilateInto(cells, box.d, w, kNearEmpty, [](uint8_t c) { return (c & kOutside) != 0; });
  dilateInto(cells, box.d, w, kNearEnamel, [](uint8_t c) { return classOf(c) == kEnamel; });
  if (caries) dilateInto(cells, box.d, w, kNearHard, [](uint8_t c) { return classOf(c) >= kDentin; });
  std::vector<std::pair<uint64_t, uint8_t>> changes;
  for (uint64_t o = 0; o < cells.size(); ++o) {
    const uint8_t c = cells[o], cls = classOf(c);
    if (!(c & kNearEmpty)) continue;
    uint8_t bright = 0;
    if (cls == kDentin && (c & kNearEnamel)) bright = kEnamel;
    if (cls == kCaries && (c & kNearHard)) bright = (c & kNearEnamel) ? kEnamel : kDentin;
    if (bright == 0) continue;
    changes.emplace_back(o, double(box.value(o)) > means.midpoint(0, bright) ? bright : uint8_t(0));
  }
  for (const auto& [o, cls] : changes) cells[o] = uint8_t((cells[o] & ~kClassMask) | cls);
  for (uint8_t& c : cells) c = classOf(c);
  return changes.size();
}

// Mean value of the empty space facing the tooth: [0] the outside, [1] enclosed space; `fallback`
// where there is none. Cut-away hard tissue (value >= hard) is in neither.
std::array<double, 2> darkMeans(const BoxCells& box, double hard, double fallback) {
  double sum[2] = {0, 0}, cnt[2] = {0, 0};
  for (uint64_t o = 0; o < box.cells.size(); ++o) {
    if (classOf(box.cells[o]) != 0) continue;
    const float v = box.value(o);
    if (!(v < hard)) continue;  // cut-away hard tissue and non-finite values
    const int side = (box.cells[o] & kOutside) ? 0 : 1;
    sum[side] += double(v);
    cnt[side] += 1;
  }
  std::array<double, 2> out{fallback, fallback};
  for (size_t side = 0; side < 2; ++side)
    if (cnt[side] > 0) out[side] = sum[side] / cnt[side];
  return out;
}

// Edges: a tooth voxel facing empty space is kept when its value is at least half-way from the
// mean of that space to its class's mean, peeled up to `layers` times. One global cut is half-way
// between air and dentin, which leaves a rim of dentin in the pulp, whose soft tissue is far
// brighter than air. Needs kOutside marked; returns the voxels emptied.
uint64_t applyEdgeRule(BoxCells& box, int layers, const std::array<double, 2>& dark, const ClassMeans& means) {
  std::vector<uint8_t>& cells = box.cells;
  uint64_t emptied = 0;
  for (int pass = 0; pass < layers; ++pass) {
    std::vector<std::pair<uint64_t, uint8_t>> changes;
    for (uint64_t o = 0; o < cells.size(); ++o) {
      const uint8_t cls = classOf(cells[o]);
      if (cls == 0) continue;
      bool faces_out = false, faces_in = false;
      forEachFaceNeighbour(o, box.d, [&](uint64_t j) {
        if (classOf(cells[j]) != 0) return;
        if (cells[j] & kOutside) faces_out = true;
        else faces_in = true;
      });
      if (!faces_out && !faces_in) continue;
      if (double(box.value(o)) < 0.5 * (dark[faces_in ? 1 : 0] + means.mean[cls]))
        changes.emplace_back(o, faces_out ? kOutside : uint8_t(0));
    }
    if (changes.empty()) break;
    for (const auto& [o, mark] : changes) cells[o] = mark;
    emptied += changes.size();
  }
  return emptied;
}

// Caries: 6-connected pieces of caries within w of the outside (open to the surface) and holding a
// voxel whose six neighbours are all caries (thicker than an edge rim) stay; the rest become dentin
// above the midpoint of the dentin mean and the mean of the space they lie by, else empty. Needs
// kOutside marked; returns the caries voxels rejected.
uint64_t keepOpenCaries(BoxCells& box, int w, const std::array<double, 2>& dark, const ClassMeans& means,
                        std::deque<uint64_t>& queue) {
  std::vector<uint8_t>& cells = box.cells;
  dilateInto(cells, box.d, w, kNearEmpty, [](uint8_t c) { return (c & kOutside) != 0; });
  uint64_t rejected = 0;
  std::vector<uint64_t> piece;
  for (uint64_t s = 0; s < cells.size(); ++s) {
    if (classOf(cells[s]) != kCaries || (cells[s] & kScratchA)) continue;
    piece.clear();
    bool open = false, thick = false;
    cells[s] |= kScratchA;
    queue.push_back(s);
    while (!queue.empty()) {
      const uint64_t o = queue.front();
      queue.pop_front();
      piece.push_back(o);
      open = open || (cells[o] & kNearEmpty);
      int caries_faces = 0;
      forEachFaceNeighbour(o, box.d, [&](uint64_t j) {
        if (classOf(cells[j]) != kCaries) return;
        ++caries_faces;
        if (!(cells[j] & kScratchA)) {
          cells[j] |= kScratchA;
          queue.push_back(j);
        }
      });
      thick = thick || caries_faces == 6;
    }
    if (open && thick) continue;
    const double split = 0.5 * (dark[open ? 0 : 1] + means.mean[kDentin]);
    for (uint64_t o : piece) {
      const uint8_t cls = double(box.value(o)) > split ? kDentin : 0;
      cells[o] = uint8_t((cells[o] & ~kClassMask) | cls);
    }
    rejected += piece.size();
  }
  for (uint8_t& c : cells) c = classOf(c);
  return rejected;
}

}  // namespace

// ---- 7. thresholds -------------------------------------------------------------------------
namespace {

struct Thresholds {
  double hard = 0;                    // hard tissue starts here (dentin_above)
  std::optional<double> caries_below; // with caries: dentin starts here
  double enamel = 0;                  // enamel_above
  std::string from_hard, from_caries, from_enamel;
  bool enamel_automatic = false, caries_automatic = false;  // refined on the tooth's voxels
};

// The lower bound of dentin: caries_below with caries, else the hard threshold.
double dentinFloor(const Thresholds& t) { return t.caries_below.value_or(t.hard); }

Status checkOrder(const Thresholds& t, GreyUnit unit, const std::string& where) {
  const std::string u = std::string(" ") + greyUnitName(unit);
  if (t.caries_below) {
    if (!(t.hard < *t.caries_below && *t.caries_below < t.enamel))
      return makeError(where, "thresholds out of order: need dentin_above " + num(t.hard) + " < caries_below " +
                                  num(*t.caries_below) + " < enamel_above " + num(t.enamel) + u);
  } else if (!(t.hard < t.enamel)) {
    return makeError(where, "thresholds out of order: dentin_above " + num(t.hard) + u +
                                " is not below enamel_above " + num(t.enamel) + u);
  }
  return Ok{};
}

// Presets first, then given values one by one, then Otsu on the ROI for whatever is still unset.
Result<Thresholds> chooseThresholds(const RoiView& roi, const ToothSegmentOptions& o, GreyUnit unit) {
  Thresholds t;
  std::optional<double> hard, caries_below, enamel;
  if (!o.preset.empty()) {
    const auto& presets = toothSegmentPresets();
    const auto it = std::find_if(presets.begin(), presets.end(),
                                 [&](const ToothSegmentPreset& p) { return o.preset == p.name; });
    if (it == presets.end())
      return makeError(o.where, "unknown scanner preset \"" + o.preset + "\" (known: " + toothSegmentPresetNames() + ")");
    if (it->unit != unit)
      return makeError(o.where, "preset " + o.preset + " is for images in " + greyUnitName(it->unit) +
                                    ", this image is in " + greyUnitName(unit));
    hard = o.caries ? it->caries_above : it->dentin_above;
    if (o.caries) caries_below = it->dentin_above;
    enamel = it->enamel_above;
    t.from_hard = t.from_caries = t.from_enamel = "preset " + o.preset;
  }
  if (o.dentin_above) { hard = o.dentin_above; t.from_hard = "given"; }
  if (o.caries && o.caries_below) { caries_below = o.caries_below; t.from_caries = "given"; }
  if (o.enamel_above) { enamel = o.enamel_above; t.from_enamel = "given"; }
  for (const std::optional<double>& v : {hard, caries_below, enamel})
    if (v && !std::isfinite(*v)) return makeError(o.where, "a threshold is not a finite number");

  if (!hard || !enamel || (o.caries && !caries_below)) {
    // Three classes even with caries: a lesion is a small share of a ROI, too small for a class of its
    // own (4-class Otsu cuts through the lesion's own values); its cut comes from the tooth's dentin.
    const int classes = 3;
    const Histogram h = robustHistogram([&](auto&& f) { roi.forEach([&](uint64_t, float v) { f(v); }); });
    if (h.total == 0) return makeError(o.where, "the ROI holds no finite grey value");
    const std::vector<double> cuts = otsuThresholds(h, classes);
    const std::string how = "automatic (" + std::to_string(classes) + "-class Otsu on the ROI's histogram)";
    if (!hard) { hard = cuts.front(); t.from_hard = how; }
    if (o.caries && !caries_below) {
      caries_below = 0.5 * (cuts.front() + cuts.back());  // a placeholder until the tooth is known
      t.from_caries = "automatic (3 sigma below the tooth's dentin peak)";
      t.caries_automatic = true;
    }
    if (!enamel) {
      enamel = cuts.back();
      t.from_enamel = "automatic (half-way between the tooth's dentin and enamel peaks)";
      t.enamel_automatic = true;
    }
  }
  t.hard = *hard;
  t.caries_below = caries_below;
  t.enamel = *enamel;
  if (Status s = checkOrder(t, unit, o.where); !s) return s.error();
  return t;
}

// Marks a tooth voxel of the output box before it has a class.
constexpr uint8_t kToothMark = kDentin;

// Automatic caries and enamel cuts, again from the tooth's voxels alone (cells marked kToothMark):
// caries, dentin and enamel values and their edges, without the air and soft tissue that swamp the
// ROI's histogram.
Status refineOnTooth(Thresholds& thr, const BoxCells& box, GreyUnit unit, const std::string& where) {
  if (!thr.enamel_automatic && !thr.caries_automatic) return Ok{};
  const auto toothValues = [&](double lo, double hi) {
    return robustHistogram([&](auto&& f) {
      for (uint64_t o = 0; o < box.cells.size(); ++o) {
        if (box.cells[o] != kToothMark) continue;
        const float v = box.value(o);
        if (v >= lo && v < hi) f(v);
      }
    });
  };
  if (thr.enamel_automatic) {
    const Histogram h = toothValues(thr.caries_automatic ? thr.hard : dentinFloor(thr), std::numeric_limits<double>::infinity());
    if (h.total > 0) {
      // Otsu splits dentin from enamel, but the blurred edges of the surface (values between air and
      // dentin) pull its cut down. The cut is then half-way between the two sides' peaks: where a
      // blurred dentin-enamel edge crosses half its step, whatever the edges and the classes' sizes.
      const double floor = thr.caries_automatic ? thr.hard : dentinFloor(thr);
      const double otsu = otsuThresholds(h, 2).back();
      size_t below = 0, above = h.count.size() - 1;
      for (size_t b = 0; b < h.count.size(); ++b) {
        if (h.centre(b) < otsu && h.count[b] > h.count[below]) below = b;
        if (h.centre(b) >= otsu && (h.centre(above) < otsu || h.count[b] > h.count[above])) above = b;
      }
      const double cut = h.centre(above) > otsu && h.centre(below) < otsu ? 0.5 * (h.centre(below) + h.centre(above)) : otsu;
      thr.enamel = std::max(cut, std::nextafter(floor, 1e300));
    }
  }
  if (thr.caries_automatic) {
    // Sound dentin is the peak of the tooth's values below enamel (it outnumbers a lesion and the
    // blurred edges), and its spread is read from the peak's upper half, where neither lesion nor
    // edges reach: half width at half maximum = 1.1774 sigma. Demineralised tissue lies more than
    // 3 sigma below sound dentin, and at least at the hard-tissue cut.
    const Histogram h = toothValues(thr.hard, thr.enamel);
    if (h.total > 0) {
      size_t peak = 0;
      for (size_t b = 1; b < h.count.size(); ++b)
        if (h.count[b] > h.count[peak]) peak = b;
      size_t half = peak;
      while (half + 1 < h.count.size() && h.count[half] > 0.5 * h.count[peak]) ++half;
      const double sigma = std::max(h.width, (h.centre(half) - h.centre(peak)) / 1.1774);
      thr.caries_below = std::clamp(h.centre(peak) - 3.0 * sigma, std::nextafter(thr.hard, 1e300),
                                    std::nextafter(thr.enamel, -1e300));
    }
  }
  return checkOrder(thr, unit, where);
}

// Classes of the tooth's cells (marked kToothMark) by value, and each class's mean value; class 0's
// mean is over the empty cells below the hard threshold (cut-away hard tissue is in no mean).
ClassMeans classify(BoxCells& box, const Thresholds& thr) {
  std::array<double, 4> sum{}, cnt{};
  const double dentin_floor = dentinFloor(thr);
  for (uint64_t o = 0; o < box.cells.size(); ++o) {
    const float v = box.value(o);
    uint8_t cls = 0;
    if (box.cells[o] == kToothMark)
      cls = v >= thr.enamel ? kEnamel : v >= dentin_floor ? kDentin : kCaries;
    else if (!(v < thr.hard))
      continue;
    box.cells[o] = cls;
    sum[cls] += double(v);
    cnt[cls] += 1;
  }
  ClassMeans means;
  const double fallback[4] = {thr.hard, thr.hard, dentin_floor, thr.enamel};
  for (size_t c = 0; c < 4; ++c) means.mean[c] = cnt[c] > 0 ? sum[c] / cnt[c] : fallback[c];
  return means;
}

std::string thresholdsFrom(const Thresholds& t) {
  const bool automatic = t.from_hard.rfind("automatic", 0) == 0 && t.enamel_automatic &&
                         (!t.caries_below || t.from_caries.rfind("automatic", 0) == 0);
  if (automatic)
    return std::string("automatic (3-class Otsu on the ROI's histogram, enamel_above half-way between the tooth's "
                       "dentin and enamel peaks") +
           (t.caries_below ? ", caries_below 3 sigma below the tooth's dentin peak)" : ")");
  const bool same = t.from_hard == t.from_enamel && (!t.caries_below || t.from_caries == t.from_hard);
  if (same) return t.from_hard;
  std::string out = "dentin_above " + t.from_hard;
  if (t.caries_below) out += ", caries_below " + t.from_caries;
  return out + ", enamel_above " + t.from_enamel;
}

// The ROI as a voxel box of the image.
Result<Box> roiBox(const GreyImage& image, const std::array<double, 12>& inv, const ToothSegmentOptions& o) {
  Box box;
  box.hi = {image.dims[0] - 1, image.dims[1] - 1, image.dims[2] - 1};
  if (!o.roi) return box;
  const MmBox& r = *o.roi;
  std::array<double, 3> vmin, vmax;
  vmin.fill(std::numeric_limits<double>::infinity());
  vmax.fill(-std::numeric_limits<double>::infinity());
  for (int c = 0; c < 8; ++c) {
    const std::array<double, 3> p = {(c & 1) ? r.hi[0] : r.lo[0], (c & 2) ? r.hi[1] : r.lo[1], (c & 4) ? r.hi[2] : r.lo[2]};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return makeError(o.where, "the ROI has a corner that is not a finite number");
    const std::array<double, 3> v = applyAffine(inv, p);
    for (size_t a = 0; a < 3; ++a) {
      vmin[a] = std::min(vmin[a], v[a]);
      vmax[a] = std::max(vmax[a], v[a]);
    }
  }
  const std::string said = "the ROI " + mmPoint(r.lo) + " .. " + mmPoint(r.hi);
  constexpr double kSlack = 1e-6;  // voxels: corners placed on voxel centres by float arithmetic
  for (size_t a = 0; a < 3; ++a) {
    const double lo = std::ceil(vmin[a] - kSlack), hi = std::floor(vmax[a] + kSlack);
    if (lo > hi) return makeError(o.where, said + " holds no voxel centre");
    if (hi < 0 || lo > double(image.dims[a] - 1))
      return makeError(o.where, said + " lies outside the image (" + std::to_string(image.dims[0]) + " x " +
                                    std::to_string(image.dims[1]) + " x " + std::to_string(image.dims[2]) + " voxels)");
    box.lo[a] = int64_t(std::max(lo, 0.0));
    box.hi[a] = int64_t(std::min(hi, double(image.dims[a] - 1)));
  }
  return box;
}


}  // namespace

// ---- 8. segmentTooth ------------------------------------------------------------------------

Result<LabelImage> segmentTooth(const GreyImage& image, const ToothSegmentOptions& options,
                                Interrupter& interrupter, ToothSegmentReport* report) {
  ToothSegmentReport local;
  ToothSegmentReport& rep = report ? *report : local;
  rep = ToothSegmentReport{};
  rep.unit = image.unit;
  const std::string& where = options.where;
  const std::string unit = std::string(" ") + greyUnitName(image.unit);

  if (image.dims[0] <= 0 || image.dims[1] <= 0 || image.dims[2] <= 0 || image.values.empty())
    return makeError(where, "the image is empty");
  if (image.values.size() != uint64_t(image.voxelCount()))
    return makeError(where, "the image holds " + std::to_string(image.values.size()) + " values for " +
                                std::to_string(image.voxelCount()) + " voxels");
  if (options.min_island_mm3 < 0 || !std::isfinite(options.min_island_mm3))
    return makeError(where, "min_island_mm3 must be a number >= 0, not " + num(options.min_island_mm3));
  if (options.partial_volume_voxels < 0 || options.margin_voxels < 0 || !(options.split_h_mm >= 0))
    return makeError(where, "partial-volume width, margin and split height must be >= 0");
  std::array<double, 12> inv{};
  if (!invertAffine(image.scanner_from_voxel, inv)) return makeError(where, "the scanner matrix is singular");

  interrupter.start("segmenting the tooth");
  const Stage job{interrupter, 0.0, 1.0};

  // ROI and thresholds.
  Result<Box> roi_box = roiBox(image, inv, options);
  if (!roi_box) return roi_box.error();
  const RoiView roi{image, *roi_box, roi_box->dims()};
  rep.roi_lo = roi.box.lo;
  rep.roi_hi = roi.box.hi;
  Result<Thresholds> chosen = chooseThresholds(roi, options, image.unit);
  if (!chosen) return chosen.error();
  Thresholds thr = *chosen;
  if (!job.report(0.1)) return cancelled(where);

  // The hard mask over the ROI.
  const uint64_t n_roi = roi.box.count();
  Bits hard(n_roi);
  uint64_t hard_count = 0;
  roi.forEach([&](uint64_t l, float v) {
    if (v >= thr.hard) {
      hard.set(l);
      ++hard_count;
    }
  });
  if (hard_count == 0)
    return makeError(where, "no voxel reaches the dentin threshold " + num(thr.hard) + unit);

  // The seed, when given, in ROI-local coordinates.
  std::optional<uint64_t> seed_local;
  if (options.seed_mm) {
    const std::array<double, 3>& s = *options.seed_mm;
    const std::array<double, 3> v = applyAffine(inv, s);
    std::array<int64_t, 3> c{};
    for (size_t a = 0; a < 3; ++a) {
      const double r = std::round(v[a]);
      if (!(r >= 0 && r <= double(image.dims[a] - 1)))
        return makeError(where, "the seed " + mmPoint(s) + " is outside the image");
      c[a] = int64_t(r);
    }
    for (size_t a = 0; a < 3; ++a)
      if (c[a] < roi.box.lo[a] || c[a] > roi.box.hi[a])
        return makeError(where, "the seed " + mmPoint(s) + " is outside the ROI");
    const uint64_t l = localIndex({c[0] - roi.box.lo[0], c[1] - roi.box.lo[1], c[2] - roi.box.lo[2]}, roi.d);
    if (!hard.test(l))
      return makeError(where, "the seed " + mmPoint(s) + " is not in hard tissue: value " +
                                  num(image.values[image.index(c[0], c[1], c[2])]) + unit + " (dentin_above " +
                                  num(thr.hard) + unit + ")");
    seed_local = l;
    rep.seeded = true;
  }

  // The tooth: the seed's piece cut at narrow joins, or the largest piece.
  std::deque<uint64_t> queue;
  Result<ToothMask> found = findTooth(roi, hard, seed_local, image.pitch_mm, options, Stage{interrupter, 0.1, 0.6}, queue, rep);
  if (!found) return found.error();
  // A ROI of air or soft tissue alone still splits into "classes" of noise; what it calls a tooth is
  // then a speck. No tooth is smaller than min_tooth_mm3, so a speck is an error, not a tooth.
  const double tooth_mm3 = double(rep.tooth_voxels) * image.pitch_mm[0] * image.pitch_mm[1] * image.pitch_mm[2];
  if (tooth_mm3 < options.min_tooth_mm3)
    return makeError(where, std::string(rep.seeded ? "the seed's tooth" : "the largest piece of hard tissue") + " is only " +
                                num(tooth_mm3) + " mm^3 (hard from " + num(thr.hard) + unit +
                                "): no tooth here; check the ROI, or give the thresholds");
  const Box& tooth_box = found->box;
  hard = Bits();
  if (!job.report(0.6)) return cancelled(where);

  // The output box: the tooth's box and a margin, within the ROI (local, then image coordinates).
  Box out_local;
  for (size_t a = 0; a < 3; ++a) {
    out_local.lo[a] = std::max<int64_t>(0, tooth_box.lo[a] - options.margin_voxels);
    out_local.hi[a] = std::min<int64_t>(roi.d[a] - 1, tooth_box.hi[a] + options.margin_voxels);
    rep.out_lo[a] = roi.box.lo[a] + out_local.lo[a];
    rep.out_hi[a] = roi.box.lo[a] + out_local.hi[a];
  }
  const std::array<int32_t, 3> od = out_local.dims();
  const uint64_t n_out = out_local.count();
  BoxCells box{image, rep.out_lo, od, std::vector<uint8_t>(n_out, 0)};
  {
    size_t o = 0;
    for (int64_t z = out_local.lo[2]; z <= out_local.hi[2]; ++z)
      for (int64_t y = out_local.lo[1]; y <= out_local.hi[1]; ++y)
        for (int64_t x = out_local.lo[0]; x <= out_local.hi[0]; ++x, ++o)
          if (found->bits.test(localIndex({x, y, z}, roi.d))) box.cells[o] = kToothMark;
  }
  found->bits = Bits();

  // Thresholds refined on the tooth, then classes and their means.
  if (Status s = refineOnTooth(thr, box, image.unit, where); !s) return s.error();
  rep.dentin_above = thr.hard;
  rep.enamel_above = thr.enamel;
  rep.caries_below = thr.caries_below;
  rep.thresholds_from = thresholdsFrom(thr);
  const ClassMeans means = classify(box, thr);
  if (!job.report(0.7)) return cancelled(where);

  // Partial volume, then the outside again (the rule empties the rim), then edges and caries.
  const int w = options.partial_volume_voxels;
  if (w > 0) rep.partial_volume_voxels = applyPartialVolume(box, w, options.caries, means, queue);
  if (!job.report(0.8)) return cancelled(where);

  markOutside(box.cells, box.d, queue);
  const std::array<double, 2> dark = darkMeans(box, thr.hard, means.mean[0]);
  rep.edge_voxels = applyEdgeRule(box, w, dark, means);
  if (options.caries) rep.caries_rejected_voxels = keepOpenCaries(box, std::max(w, 1), dark, means, queue);
  if (!job.report(0.85)) return cancelled(where);

  // Islands, through importLabels' own rule, on voxel codes.
  std::vector<uint8_t>& cells = box.cells;
  for (uint8_t& c : cells) {
    c = classOf(c);
    c = c == kEnamel ? makeVoxel(Material::Enamel) : c == kDentin ? makeVoxel(Material::Dentin)
                                                 : c == kCaries ? makeVoxel(Material::Caries) : Voxel(0);
  }
  const double voxel_mm3 = image.pitch_mm[0] * image.pitch_mm[1] * image.pitch_mm[2];
  rep.min_island_voxels = options.min_island_mm3 / voxel_mm3;
  const int64_t min_voxels = int64_t(std::ceil(rep.min_island_voxels - 1e-9));
  if (min_voxels > 1) {
    PieceCleanup cleanup;
    StageInterrupter sub(Stage{interrupter, 0.85, 0.99});
    Status s = cleanSmallPieces(cells, od, min_voxels, cleanup, sub, where);
    if (sub.cancelled) return cancelled(where);
    if (!s) return s.error();
    for (size_t m = 0; m < cleanup.pieces.size(); ++m) {
      rep.islands_removed += cleanup.pieces[m];
      rep.island_voxels += cleanup.voxels[m];
    }
  }

  // The label image: tissue table labels, the image's geometry shifted to the box.
  LabelImage out;
  out.dims = od;
  out.pitch_mm = image.pitch_mm;
  out.scanner_from_voxel = image.scanner_from_voxel;
  const std::array<double, 3> origin = applyAffine(image.scanner_from_voxel,
                                                   {double(rep.out_lo[0]), double(rep.out_lo[1]), double(rep.out_lo[2])});
  for (size_t r = 0; r < 3; ++r) out.scanner_from_voxel[4 * r + 3] = origin[r];
  out.labels.resize(n_out);
  for (uint64_t o = 0; o < n_out; ++o) {
    const Material m = static_cast<Material>(voxelMaterial(cells[o]));
    const TissueRow* row = findTissue(m);
    out.labels[o] = row ? Label(row->nifti_label) : Label(0);
    rep.enamel_voxels += m == Material::Enamel;
    rep.dentin_voxels += m == Material::Dentin;
    rep.caries_voxels += m == Material::Caries;
  }
  if (!job.report(1.0)) return cancelled(where);
  interrupter.end();
  return out;
}

}  // namespace dentsim
