// Tests of src/volume/ct_segment.cpp: Otsu on known histograms, and segmentation of blurred, noisy phantoms against their known labels.
//
// The phantom's grey model (HU): air -1000, pulp 40, caries 800, bone 1200, dentin 1500, enamel
// 2800; blurred by a Gaussian of sigma 1 voxel (a scanner's point spread), then normal noise of
// sigma 80 HU from std::mt19937 with a fixed seed. Pitch 0.1 mm. Tooth A: a dentin ball of radius
// 18 voxels around a pulp of radius 7, under an enamel cap (radius 18..24) over its upper part.
// Optional: tooth B (dentin ball radius 10, enamel to 13) touching A's cap at one voxel; a bone
// slab 14 voxels thick under A, joined to it by a neck of radius 1.5 voxels; a caries blob of
// radius 6 on A's dentin surface.
#include "volume/ct_segment.h"

#include "volume/label_import.h"
#include "volume/tissue_boundary_rules.h"
#include "volume/tissue_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <random>
#include <vector>

namespace dentsim {
namespace {

// Phantom truth codes.
enum Truth : uint8_t { kAir = 0, kEnamelA = 1, kDentinA = 2, kPulpA = 3, kCariesA = 4, kBone = 5, kEnamelB = 6, kDentinB = 7 };

constexpr double kPitch = 0.1;                         // [mm]
constexpr std::array<double, 3> kOrigin{10.0, 20.0, 30.0};  // scanner position of voxel (0,0,0) [mm]
constexpr std::array<int, 3> kCentreA{28, 28, 44};     // tooth A's centre [voxels]

float greyOf(uint8_t t) {
  switch (t) {
    case kEnamelA: case kEnamelB: return 2800.0f;
    case kDentinA: case kDentinB: return 1500.0f;
    case kPulpA: return 40.0f;
    case kCariesA: return 800.0f;
    case kBone: return 1200.0f;
    default: return -1000.0f;
  }
}

struct PhantomSpec {
  bool neighbour = false, bone = false, caries = false;
};

struct Phantom {
  std::array<int32_t, 3> dims{82, 58, 72};
  std::vector<uint8_t> truth;
  GreyImage image;
  size_t index(int i, int j, int k) const { return size_t(i + dims[0] * (j + dims[1] * k)); }
  uint64_t count(uint8_t t) const { return uint64_t(std::count(truth.begin(), truth.end(), t)); }
};

double dist(int i, int j, int k, const std::array<int, 3>& c) {
  return std::sqrt(double((i - c[0]) * (i - c[0]) + (j - c[1]) * (j - c[1]) + (k - c[2]) * (k - c[2])));
}

// Separable Gaussian blur, sigma 1 voxel, edges clamped.
void blur(std::vector<float>& v, const std::array<int32_t, 3>& d) {
  float kernel[7];
  float total = 0;
  for (int t = -3; t <= 3; ++t) total += kernel[t + 3] = std::exp(-0.5f * float(t * t));
  for (float& k : kernel) k /= total;
  std::vector<float> out(v.size());
  const int stride[3] = {1, d[0], d[0] * d[1]};
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int c[3] = {i, j, k};
          const size_t base = size_t(i + d[0] * (j + d[1] * k));
          float s = 0;
          for (int t = -3; t <= 3; ++t) {
            const int p = std::clamp(c[a] + t, 0, d[a] - 1);
            s += kernel[t + 3] * v[base + size_t((p - c[a]) * stride[a])];
          }
          out[base] = s;
        }
    v.swap(out);
  }
}

Phantom makePhantom(const PhantomSpec& spec) {
  Phantom ph;
  const auto& d = ph.dims;
  ph.truth.assign(size_t(d[0]) * d[1] * d[2], kAir);
  const std::array<int, 3> cb{kCentreA[0] + 37, kCentreA[1], kCentreA[2]};
  const std::array<int, 3> blob{kCentreA[0] - 14, kCentreA[1], kCentreA[2] - 11};
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        uint8_t& t = ph.truth[ph.index(i, j, k)];
        const double ra = dist(i, j, k, kCentreA);
        if (ra <= 7) t = kPulpA;
        else if (ra <= 18) t = (spec.caries && dist(i, j, k, blob) <= 6) ? kCariesA : kDentinA;
        else if (ra <= 24 && k > kCentreA[2] - 6) t = kEnamelA;
        if (t != kAir) continue;
        if (spec.neighbour) {
          const double rb = dist(i, j, k, cb);
          if (rb <= 10) t = kDentinB;
          else if (rb <= 13) t = kEnamelB;
        }
        if (spec.bone) {
          const double axis = std::hypot(double(i - kCentreA[0]), double(j - kCentreA[1]));
          const bool slab = k >= 7 && k <= 20 && std::abs(i - kCentreA[0]) <= 20 && std::abs(j - kCentreA[1]) <= 20;
          const bool neck = k > 20 && k <= kCentreA[2] - 17 && axis <= 1.5;
          if (slab || neck) t = kBone;
        }
      }
  GreyImage& im = ph.image;
  im.dims = d;
  im.pitch_mm = {kPitch, kPitch, kPitch};
  im.scanner_from_voxel = {kPitch, 0, 0, kOrigin[0], 0, kPitch, 0, kOrigin[1], 0, 0, kPitch, kOrigin[2]};
  im.unit = GreyUnit::Hounsfield;
  im.values.resize(ph.truth.size());
  for (size_t n = 0; n < ph.truth.size(); ++n) im.values[n] = greyOf(ph.truth[n]);
  blur(im.values, d);
  std::mt19937 rng(20261128);
  std::normal_distribution<float> noise(0.0f, 80.0f);
  for (float& v : im.values) v += noise(rng);
  return ph;
}

// The output's label at image voxel (i,j,k), 0 outside the output box.
Label labelAt(const LabelImage& out, const ToothSegmentReport& rep, int i, int j, int k) {
  const int64_t x = i - rep.out_lo[0], y = j - rep.out_lo[1], z = k - rep.out_lo[2];
  if (x < 0 || y < 0 || z < 0 || x >= out.dims[0] || y >= out.dims[1] || z >= out.dims[2]) return 0;
  return out.labels[out.index(x, y, z)];
}

// Dice of (output == label) against (truth in `truth_codes`) over the whole image.
double dice(const Phantom& ph, const LabelImage& out, const ToothSegmentReport& rep, Label label,
            std::initializer_list<uint8_t> truth_codes) {
  uint64_t a = 0, b = 0, both = 0;
  for (int k = 0; k < ph.dims[2]; ++k)
    for (int j = 0; j < ph.dims[1]; ++j)
      for (int i = 0; i < ph.dims[0]; ++i) {
        const bool x = labelAt(out, rep, i, j, k) == label;
        const uint8_t t = ph.truth[ph.index(i, j, k)];
        const bool y = std::find(truth_codes.begin(), truth_codes.end(), t) != truth_codes.end();
        a += x;
        b += y;
        both += x && y;
      }
  return a + b == 0 ? 1.0 : 2.0 * double(both) / double(a + b);
}

// Output voxels with `label` where the truth is one of `codes`.
uint64_t countWhere(const Phantom& ph, const LabelImage& out, const ToothSegmentReport& rep, Label label,
                    std::initializer_list<uint8_t> codes) {
  uint64_t n = 0;
  for (int k = 0; k < ph.dims[2]; ++k)
    for (int j = 0; j < ph.dims[1]; ++j)
      for (int i = 0; i < ph.dims[0]; ++i)
        if (labelAt(out, rep, i, j, k) == label &&
            std::find(codes.begin(), codes.end(), ph.truth[ph.index(i, j, k)]) != codes.end())
          ++n;
  return n;
}

std::array<double, 3> mmOf(const GreyImage& im, std::array<double, 3> v) {
  const auto& m = im.scanner_from_voxel;
  std::array<double, 3> p{};
  for (size_t r = 0; r < 3; ++r) p[r] = m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2] + m[4 * r + 3];
  return p;
}

// A point in A's dentin, below the pulp.
std::array<double, 3> seedA(const GreyImage& im) {
  return mmOf(im, {double(kCentreA[0]), double(kCentreA[1]), double(kCentreA[2] - 12)});
}

// ---- Otsu ---------------------------------------------------------------------------------------

TEST(CtSegmentOtsu, ThreeSpikesGiveTwoCutsBetweenThem) {
  std::vector<double> h(256, 0.0);
  h[20] = 1000;
  h[100] = 500;
  h[200] = 300;
  const std::vector<size_t> cuts = internal::otsuCuts(h, 3);
  ASSERT_EQ(cuts.size(), 2u);
  // A cut b puts bin b in the upper class: any b in (20, 100] and (100, 200] separates the spikes.
  EXPECT_GT(cuts[0], 20u);
  EXPECT_LE(cuts[0], 100u);
  EXPECT_GT(cuts[1], 100u);
  EXPECT_LE(cuts[1], 200u);
}

TEST(CtSegmentOtsu, FourSpikesAndTwoClassesKnownAnswer) {
  std::vector<double> h(64, 0.0);
  h[5] = 10;
  h[20] = 10;
  h[40] = 10;
  h[60] = 10;
  const std::vector<size_t> four = internal::otsuCuts(h, 4);
  ASSERT_EQ(four.size(), 3u);
  EXPECT_TRUE(four[0] > 5 && four[0] <= 20);
  EXPECT_TRUE(four[1] > 20 && four[1] <= 40);
  EXPECT_TRUE(four[2] > 40 && four[2] <= 60);
  // Two equal spikes at 0 and 10 and a third at 30 (weights 1, 1, 2): splitting {0, 10} | {30}
  // gives between-class sums 10^2/2 + 60^2/2 = 1850 against 0 + 70^2/3 = 1633.3 for {0} | {10, 30}.
  std::vector<double> g(32, 0.0);
  g[0] = 1;
  g[10] = 1;
  g[30] = 2;
  const std::vector<size_t> two = internal::otsuCuts(g, 2);
  ASSERT_EQ(two.size(), 1u);
  EXPECT_TRUE(two[0] > 10 && two[0] <= 30) << two[0];
}

// ---- tissues against known labels -----------------------------------------------------------

TEST(CtSegment, AutomaticThresholdsLieBetweenClassesAndDiceIsHigh) {
  const Phantom ph = makePhantom({});
  ToothSegmentOptions o;
  o.where = "phantom";
  ToothSegmentReport rep;
  Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &rep);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_GT(rep.dentin_above, -1000.0);
  EXPECT_LT(rep.dentin_above, 1500.0);
  EXPECT_GT(rep.enamel_above, 1500.0);
  EXPECT_LT(rep.enamel_above, 2800.0);
  EXPECT_EQ(rep.thresholds_from,
            "automatic (3-class Otsu on the ROI's histogram, enamel_above half-way between the tooth's dentin and "
            "enamel peaks)");
  const double de = dice(ph, *r, rep, 1, {kEnamelA}), dd = dice(ph, *r, rep, 2, {kDentinA});
  std::printf("automatic: dentin_above %.0f, enamel_above %.0f HU; Dice enamel %.4f, dentin %.4f; partial volume %llu\n",
              rep.dentin_above, rep.enamel_above, de, dd, (unsigned long long)rep.partial_volume_voxels);
  EXPECT_GE(de, 0.95);
  EXPECT_GE(dd, 0.95);
  // The pulp stays empty but for its blurred wall: voxels whose centre lies on the pulp's edge.
  const uint64_t pulp = countWhere(ph, *r, rep, 1, {kPulpA}) + countWhere(ph, *r, rep, 2, {kPulpA});
  std::printf("pulp voxels labelled: %llu of %llu\n", (unsigned long long)pulp, (unsigned long long)ph.count(kPulpA));
  EXPECT_LT(pulp * 10, ph.count(kPulpA));
  // The report counts every tissue of the table by its label; those that are no grey class (pulp) are 0.
  for (size_t t = 0; t < kTissueCount; ++t) {
    const TissueRow& row = kTissueTable[t];
    EXPECT_EQ(rep.tissue_voxels[t], uint64_t(std::count(r->labels.begin(), r->labels.end(), Label(row.nifti_label))))
        << row.name;
    EXPECT_EQ(rep.tissue_voxels[t] > 0, tooth_cell::isGreyClass(row.material) && row.material != Material::Caries)
        << row.name;  // no caries without options.caries
  }
  EXPECT_FALSE(rep.seeded);
  // The box is the tooth's (4..52, 4..52, 26..68) plus 3, within the image; the dentin's lowest
  // voxel (a lone tip at k = 26) may blur below the cut.
  EXPECT_EQ(rep.out_lo[0], 1);
  EXPECT_EQ(rep.out_lo[1], 1);
  EXPECT_TRUE(rep.out_lo[2] == 23 || rep.out_lo[2] == 24) << rep.out_lo[2];
  EXPECT_EQ(rep.out_hi, (std::array<int64_t, 3>{55, 55, 71}));
  EXPECT_EQ(r->dims, (std::array<int32_t, 3>{55, 55, int32_t(72 - rep.out_lo[2])}));
  EXPECT_DOUBLE_EQ(r->scanner_from_voxel[3], kOrigin[0] + 1 * kPitch);
  EXPECT_DOUBLE_EQ(r->scanner_from_voxel[11], kOrigin[2] + double(rep.out_lo[2]) * kPitch);
}

TEST(CtSegment, PartialVolumeRuleRemovesTheFalseDentinRimOnEnamel) {
  const Phantom ph = makePhantom({});
  ToothSegmentOptions o;
  ToothSegmentReport on, off;
  Result<LabelImage> with = segmentTooth(ph.image, o, nullInterrupter(), &on);
  o.partial_volume_voxels = 0;
  Result<LabelImage> without = segmentTooth(ph.image, o, nullInterrupter(), &off);
  ASSERT_TRUE(with.ok() && without.ok());
  // False dentin: labelled dentin where the truth is enamel or air (the rim on the enamel's surface).
  const uint64_t rim_off = countWhere(ph, *without, off, 2, {kEnamelA, kAir});
  const uint64_t rim_on = countWhere(ph, *with, on, 2, {kEnamelA, kAir});
  const double dd_on = dice(ph, *with, on, 2, {kDentinA}), dd_off = dice(ph, *without, off, 2, {kDentinA});
  std::printf("false dentin on enamel/air: %llu without the rule, %llu with it; dentin Dice %.4f -> %.4f\n",
              (unsigned long long)rim_off, (unsigned long long)rim_on, dd_off, dd_on);
  EXPECT_GT(rim_off, 1000u);          // a rim over the cap's ~5000 surface voxels
  EXPECT_LT(rim_on * 5, rim_off);     // the rule removes most of it
  EXPECT_GT(dd_on, dd_off);
  EXPECT_GT(on.partial_volume_voxels, 0u);
  EXPECT_EQ(off.partial_volume_voxels, 0u);
}

TEST(CtSegment, GivenThresholdsAreUsedExactly) {
  const Phantom ph = makePhantom({});
  ToothSegmentOptions o;
  o.dentin_above = 600.0;
  o.enamel_above = 2000.0;
  o.partial_volume_voxels = 0;
  o.min_island_mm3 = 0;
  ToothSegmentReport rep;
  Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &rep);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(rep.dentin_above, 600.0);
  EXPECT_EQ(rep.enamel_above, 2000.0);
  EXPECT_EQ(rep.thresholds_from, "given");
  // Every labelled voxel obeys the cuts, and every voxel of the box at or above 600 HU is labelled
  // (the phantom holds one hard piece).
  for (int64_t z = 0; z < r->dims[2]; ++z)
    for (int64_t y = 0; y < r->dims[1]; ++y)
      for (int64_t x = 0; x < r->dims[0]; ++x) {
        const float v = ph.image.values[ph.image.index(x + rep.out_lo[0], y + rep.out_lo[1], z + rep.out_lo[2])];
        const Label l = r->labels[r->index(x, y, z)];
        const Label want = v >= 2000.0f ? 1 : v >= 600.0f ? 2 : 0;
        ASSERT_EQ(l, want) << x << " " << y << " " << z << " value " << v;
      }
  // A preset in HU gives both cuts.
  ToothSegmentOptions p;
  p.preset = "ct-hu";
  ToothSegmentReport prep;
  ASSERT_TRUE(segmentTooth(ph.image, p, nullInterrupter(), &prep).ok());
  EXPECT_EQ(prep.dentin_above, 1000.0);
  EXPECT_EQ(prep.enamel_above, 2100.0);
  EXPECT_EQ(prep.thresholds_from, "preset ct-hu");
}

TEST(CtSegment, IslandsTakeTheTissueAroundThem) {
  // An enamel cut 2.5 noise sigmas above dentin leaves specks of "enamel" all through the dentin.
  const Phantom ph = makePhantom({});
  ToothSegmentOptions o;
  o.dentin_above = 250.0;
  o.enamel_above = 1700.0;
  o.min_island_mm3 = 0;
  ToothSegmentReport raw, clean;
  Result<LabelImage> a = segmentTooth(ph.image, o, nullInterrupter(), &raw);
  o.min_island_mm3 = 0.01;  // 10 voxels of 0.1 mm
  Result<LabelImage> b = segmentTooth(ph.image, o, nullInterrupter(), &clean);
  ASSERT_TRUE(a.ok() && b.ok());
  // Enamel labels deep in the dentin, 5 voxels or more below the dentin-enamel junction (r = 18):
  // nearer to it, chains of specks reach the enamel layer and are part of it, not islands.
  auto specks = [&](const LabelImage& out, const ToothSegmentReport& rep) {
    uint64_t n = 0;
    for (int k = 0; k < ph.dims[2]; ++k)
      for (int j = 0; j < ph.dims[1]; ++j)
        for (int i = 0; i < ph.dims[0]; ++i)
          if (ph.truth[ph.index(i, j, k)] == kDentinA && dist(i, j, k, kCentreA) <= 13 &&
              labelAt(out, rep, i, j, k) == 1)
            ++n;
    return n;
  };
  const uint64_t specks_raw = specks(*a, raw), specks_clean = specks(*b, clean);
  std::printf("islands: %llu removed (%llu voxels); enamel specks deep in the dentin %llu -> %llu\n",
              (unsigned long long)clean.islands_removed, (unsigned long long)clean.island_voxels,
              (unsigned long long)specks_raw, (unsigned long long)specks_clean);
  EXPECT_EQ(raw.islands_removed, 0u);
  EXPECT_GT(clean.islands_removed, 20u);
  EXPECT_DOUBLE_EQ(clean.min_island_voxels, 10.0);
  EXPECT_GT(specks_raw, 20u);
  EXPECT_EQ(specks_clean, 0u);
}

TEST(CtSegment, OutputImportsWithThePulpFilledByImportLabels) {
  const Phantom ph = makePhantom({});
  Result<LabelImage> r = segmentTooth(ph.image, ToothSegmentOptions{});
  ASSERT_TRUE(r.ok()) << r.message();
  LabelImportOptions io;
  io.map = parseLabelMap("1=enamel,2=dentin,4=caries").value();
  io.fill_enclosed = Material::Pulp;
  LabelImportReport ir;
  Result<ToothVolume> tooth = importLabels(*r, io, nullInterrupter(), &ir);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  LabelImage back = exportLabels(*tooth);
  const uint64_t pulp = uint64_t(std::count(back.labels.begin(), back.labels.end(), Label(3)));
  std::printf("pulp after import: %llu voxels (truth %llu)\n", (unsigned long long)pulp,
              (unsigned long long)ph.count(kPulpA));
  EXPECT_GT(pulp, ph.count(kPulpA) * 8 / 10);
  EXPECT_LT(pulp, ph.count(kPulpA) * 12 / 10);
}

// ---- the seed cuts the tooth from its neighbours ----------------------------------------------

TEST(CtSegment, SeedKeepsTheToothAndCutsTheTouchingToothAndTheBone) {
  const Phantom ph = makePhantom({.neighbour = true, .bone = true});
  const uint64_t other = ph.count(kEnamelB) + ph.count(kDentinB) + ph.count(kBone);
  ToothSegmentOptions o;
  o.dentin_above = 250.0;  // the same cut both ways, so the pieces compare
  ToothSegmentReport whole, cut;
  // Without a seed the largest piece is A, B and the bone together: they are joined.
  Result<LabelImage> all = segmentTooth(ph.image, o, nullInterrupter(), &whole);
  ASSERT_TRUE(all.ok()) << all.message();
  const uint64_t joined = countWhere(ph, *all, whole, 1, {kEnamelB, kDentinB, kBone}) +
                          countWhere(ph, *all, whole, 2, {kEnamelB, kDentinB, kBone});
  EXPECT_GT(joined, other * 9 / 10);

  o.seed_mm = seedA(ph.image);
  Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &cut);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(cut.seeded);
  const uint64_t kept_other = countWhere(ph, *r, cut, 1, {kEnamelB, kDentinB, kBone}) +
                              countWhere(ph, *r, cut, 2, {kEnamelB, kDentinB, kBone});
  const double de = dice(ph, *r, cut, 1, {kEnamelA}), dd = dice(ph, *r, cut, 2, {kDentinA});
  std::printf("seeded: %llu of %llu neighbour and bone voxels kept (%llu before the seed), %llu cut; Dice enamel %.4f, dentin %.4f\n",
              (unsigned long long)kept_other, (unsigned long long)other, (unsigned long long)joined,
              (unsigned long long)cut.neighbour_voxels_cut, de, dd);
  // At most the two joins' few voxels: a voxel where regions meet goes to the deeper one, and A,
  // its pulp filled for the cut, is the deepest, so it takes the necks' voxels (96 in this phantom;
  // under 60 when the transform saw A hollow).
  EXPECT_LT(kept_other, 120u);
  EXPECT_GT(cut.neighbour_voxels_cut, other * 9 / 10);
  EXPECT_EQ(cut.hard_component_voxels, whole.tooth_voxels);
  EXPECT_GE(de, 0.95);
  EXPECT_GE(dd, 0.95);
}

TEST(CtSegment, RoiAndSeedFollowASwappedAndFlippedDirectionMatrix) {
  Phantom ph = makePhantom({.neighbour = true, .bone = true});
  ToothSegmentOptions o;
  o.dentin_above = 250.0;
  o.enamel_above = 2150.0;
  // Reference: identity directions, ROI over voxels (2..60, 2..56, 4..70).
  o.roi = MmBox{mmOf(ph.image, {2, 2, 4}), mmOf(ph.image, {60, 56, 70})};
  o.seed_mm = seedA(ph.image);
  ToothSegmentReport ref_rep;
  Result<LabelImage> ref = segmentTooth(ph.image, o, nullInterrupter(), &ref_rep);
  ASSERT_TRUE(ref.ok()) << ref.message();
  EXPECT_EQ(ref_rep.roi_lo, (std::array<int64_t, 3>{2, 2, 4}));
  EXPECT_EQ(ref_rep.roi_hi, (std::array<int64_t, 3>{60, 56, 70}));

  // The same voxels under x_mm = 5 + 0.1 j, y_mm = -3 + 0.1 i, z_mm = 40 - 0.1 k: i and j swapped, k flipped.
  ph.image.scanner_from_voxel = {0, kPitch, 0, 5.0, kPitch, 0, 0, -3.0, 0, 0, -kPitch, 40.0};
  o.roi = MmBox{mmOf(ph.image, {60, 2, 70}), mmOf(ph.image, {2, 56, 4})};  // corners in any order
  o.seed_mm = seedA(ph.image);
  ToothSegmentReport rep;
  Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &rep);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(rep.roi_lo, ref_rep.roi_lo);
  EXPECT_EQ(rep.roi_hi, ref_rep.roi_hi);
  EXPECT_EQ(rep.out_lo, ref_rep.out_lo);
  EXPECT_EQ(r->labels, ref->labels);
  // The output's voxel (0,0,0) is the image's out_lo, through the new matrix.
  const std::array<double, 3> o0 = mmOf(ph.image, {double(rep.out_lo[0]), double(rep.out_lo[1]), double(rep.out_lo[2])});
  EXPECT_DOUBLE_EQ(r->scanner_from_voxel[3], o0[0]);
  EXPECT_DOUBLE_EQ(r->scanner_from_voxel[7], o0[1]);
  EXPECT_DOUBLE_EQ(r->scanner_from_voxel[11], o0[2]);
  EXPECT_EQ(r->scanner_from_voxel[1], kPitch);
  EXPECT_EQ(r->scanner_from_voxel[10], -kPitch);
}

TEST(CtSegment, RoiCropGeometryByHand) {
  const Phantom ph = makePhantom({});
  ToothSegmentOptions o;
  o.dentin_above = 250.0;
  o.enamel_above = 2150.0;
  // x 12.0..14.0 mm is i 20..40; y 22.04..24.96 mm rounds inwards to j 21..49; z 34.0..36.0 mm is k 40..60.
  o.roi = MmBox{{14.0, 24.96, 36.0}, {12.0, 22.04, 34.0}};
  ToothSegmentReport rep;
  Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &rep);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(rep.roi_lo, (std::array<int64_t, 3>{20, 21, 40}));
  EXPECT_EQ(rep.roi_hi, (std::array<int64_t, 3>{40, 49, 60}));
  // The ROI lies inside the tooth's box, so the output is the ROI.
  EXPECT_EQ(rep.out_lo, rep.roi_lo);
  EXPECT_EQ(rep.out_hi, rep.roi_hi);
  EXPECT_EQ(r->dims, (std::array<int32_t, 3>{21, 29, 21}));
  EXPECT_NEAR(r->scanner_from_voxel[3], 12.0, 1e-12);
  EXPECT_NEAR(r->scanner_from_voxel[7], 22.1, 1e-12);
  EXPECT_NEAR(r->scanner_from_voxel[11], 34.0, 1e-12);
  EXPECT_EQ(r->pitch_mm, ph.image.pitch_mm);

  o.roi = MmBox{{0.0, 0.0, 0.0}, {5.0, 5.0, 5.0}};
  Result<LabelImage> outside = segmentTooth(ph.image, o);
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.message().find("lies outside the image"), std::string::npos) << outside.message();
  o.roi = MmBox{{12.0, 22.01, 34.0}, {14.0, 22.04, 36.0}};
  Result<LabelImage> empty = segmentTooth(ph.image, o);
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.message().find("holds no voxel centre"), std::string::npos) << empty.message();
  o.roi = MmBox{{12.0, 22.0, 34.0}, {14.0, 24.0, 36.0}};
  o.seed_mm = seedA(ph.image);  // k = 32, below the ROI
  Result<LabelImage> seed_out = segmentTooth(ph.image, o);
  ASSERT_FALSE(seed_out.ok());
  EXPECT_NE(seed_out.message().find("is outside the ROI"), std::string::npos) << seed_out.message();
}

// ---- caries -----------------------------------------------------------------------------------

TEST(CtSegment, CariesBlobAtTheSurfaceIsFoundAndTheEdgeRimIsNot) {
  const Phantom ph = makePhantom({.caries = true});
  const uint64_t truth = ph.count(kCariesA);
  for (bool automatic : {false, true}) {
    ToothSegmentOptions o;
    o.caries = true;
    if (!automatic) {
      o.dentin_above = -100.0;
      o.caries_below = 1150.0;
      o.enamel_above = 2150.0;
    }
    ToothSegmentReport rep;
    Result<LabelImage> r = segmentTooth(ph.image, o, nullInterrupter(), &rep);
    ASSERT_TRUE(r.ok()) << r.message();
    ASSERT_TRUE(rep.caries_below.has_value());
    const uint64_t hit = countWhere(ph, *r, rep, 4, {kCariesA});
    const uint64_t caries_voxels = rep.tissue_voxels[size_t(tissueIndex(Material::Caries))];
    // Caries anywhere but within 2 voxels of the blob is a false lesion (an edge rim called caries).
    uint64_t far = 0;
    const std::array<int, 3> blob{kCentreA[0] - 14, kCentreA[1], kCentreA[2] - 11};
    for (int k = 0; k < ph.dims[2]; ++k)
      for (int j = 0; j < ph.dims[1]; ++j)
        for (int i = 0; i < ph.dims[0]; ++i)
          if (labelAt(*r, rep, i, j, k) == 4 && dist(i, j, k, blob) > 8) ++far;
    std::printf("caries (%s: %.0f | %.0f | %.0f HU): %llu of %llu blob voxels found, %llu labelled, %llu far from it; "
                "%llu rejected; Dice enamel %.4f, dentin %.4f\n",
                automatic ? "automatic" : "given", rep.dentin_above, *rep.caries_below, rep.enamel_above,
                (unsigned long long)hit, (unsigned long long)truth, (unsigned long long)caries_voxels,
                (unsigned long long)far, (unsigned long long)rep.caries_rejected_voxels,
                dice(ph, *r, rep, 1, {kEnamelA}), dice(ph, *r, rep, 2, {kDentinA}));
    EXPECT_EQ(far, 0u);
    EXPECT_LT(*rep.caries_below, rep.enamel_above);
    EXPECT_GT(*rep.caries_below, rep.dentin_above);
    // The partial-volume rule takes the lesion's rim where it meets both air and dentin. The
    // automatic cut (3 sigma below the dentin peak: 1231 HU here, against the lesion's 800) also
    // takes a few dentin voxels at the lesion's edge, none far from it (checked above).
    EXPECT_GT(hit, truth * 3 / 10);
    EXPECT_GE(double(hit), (automatic ? 0.8 : 0.9) * double(caries_voxels));
    EXPECT_GE(dice(ph, *r, rep, 1, {kEnamelA}), 0.95);
  }
}

// ---- errors and cancellation --------------------------------------------------------------------

class CancelAfter : public Interrupter {
 public:
  explicit CancelAfter(int allow) : allow_(allow) {}
  bool progress(double fraction) override {
    EXPECT_GE(fraction, last);
    last = fraction;
    return ++calls <= allow_;
  }
  int calls = 0;
  double last = 0;

 private:
  int allow_;
};

bool oneLineNaming(const std::string& message, const std::string& where) {
  return message.rfind(where + ": ", 0) == 0 && message.find('\n') == std::string::npos;
}

TEST(CtSegment, ErrorsAreOneLineNamingTheSource) {
  ToothSegmentOptions o;
  o.where = "scan.nii";
  GreyImage empty;
  Result<LabelImage> e = segmentTooth(empty, o);
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.message(), "scan.nii: the image is empty");

  GreyImage air;
  air.dims = {8, 8, 8};
  air.scanner_from_voxel = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  air.values.assign(512, -1000.0f);
  air.unit = GreyUnit::Hounsfield;
  o.dentin_above = 500.0;
  o.enamel_above = 2000.0;
  Result<LabelImage> none = segmentTooth(air, o);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.message(), "scan.nii: no voxel reaches the dentin threshold 500 HU");

  const Phantom ph = makePhantom({});
  o.seed_mm = mmOf(ph.image, {2, 2, 2});
  Result<LabelImage> soft = segmentTooth(ph.image, o);
  ASSERT_FALSE(soft.ok());
  EXPECT_TRUE(oneLineNaming(soft.message(), "scan.nii"));
  EXPECT_NE(soft.message().find("the seed (10.2, 20.2, 30.2) mm is not in hard tissue: value "), std::string::npos)
      << soft.message();
  o.seed_mm = mmOf(ph.image, {-5, 2, 2});
  Result<LabelImage> off = segmentTooth(ph.image, o);
  ASSERT_FALSE(off.ok());
  EXPECT_EQ(off.message(), "scan.nii: the seed (9.5, 20.2, 30.2) mm is outside the image");
  o.seed_mm.reset();

  o.dentin_above = 2000.0;
  o.enamel_above = 1200.0;
  Result<LabelImage> order = segmentTooth(ph.image, o);
  ASSERT_FALSE(order.ok());
  EXPECT_EQ(order.message(), "scan.nii: thresholds out of order: dentin_above 2000 HU is not below enamel_above 1200 HU");
  o.dentin_above = 250.0;
  o.enamel_above = 2150.0;
  o.caries = true;
  o.caries_below = 3000.0;
  Result<LabelImage> corder = segmentTooth(ph.image, o);
  ASSERT_FALSE(corder.ok());
  EXPECT_EQ(corder.message(),
            "scan.nii: thresholds out of order: need dentin_above 250 < caries_below 3000 < enamel_above 2150 HU");
  o.caries = false;

  ToothSegmentOptions p;
  p.where = "scan.nii";
  p.preset = "nope";
  Result<LabelImage> unknown = segmentTooth(ph.image, p);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.message(), "scan.nii: unknown scanner preset \"nope\" (known: ct-hu, cbct-hu)");
  GreyImage raw = ph.image;
  raw.unit = GreyUnit::Raw;
  p.preset = "ct-hu";
  Result<LabelImage> unit = segmentTooth(raw, p);
  ASSERT_FALSE(unit.ok());
  EXPECT_EQ(unit.message(), "scan.nii: preset ct-hu is for images in HU, this image is in raw");

  for (int allow : {0, 2, 5}) {
    CancelAfter stop(allow);
    ToothSegmentOptions s;
    s.where = "scan.nii";
    s.seed_mm = seedA(ph.image);
    Result<LabelImage> c = segmentTooth(ph.image, s, stop);
    ASSERT_FALSE(c.ok()) << allow;
    EXPECT_EQ(c.message(), "scan.nii: segmentation cancelled");
  }
}

}  // namespace
}  // namespace dentsim
