// Surface agreement: the box around the ideal cavity, its voxel labels, two distance transforms, then one pass over the cavity's faces.
//
// Contents
//   1. The wall rule
//   2. The box and its labels
//   3. Exact squared distance transform (separable, lower envelope of parabolas)
//   4. measureSurfaceAgreement
//   5. JSON
#include "eval/surface_agreement.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "eval/tooth_diff.h"
#include "volume/tissue_table.h"
#include "volume/half_fill.h"

namespace dentsim {

// ---- 1. the wall rule ----------------------------------------------------------------------------

namespace {

Vec3 vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The wall of direction n: the direction among the insertion axis (the floor) and the tooth's axes
// across it that n faces most. False on a tie (two within rounding), unless break_ties, which then
// takes the first in report order.
bool wallOfDirection(const Vec3& n, const Vec3& axis, const ToothAxes& tooth, bool break_ties, CavityWall* out) {
  const double eps = 1e-9 * norm(n);
  const double along = dot(n, axis);
  const Vec3 across = n - axis * along;
  // The side the wall stands on is opposite to where it faces: facing distally (-mesial) is the mesial wall.
  struct Candidate {
    double component;
    CavityWall facing_minus, facing_plus;
  };
  const std::array<Candidate, 3> sides{{
      {dot(across, vec(tooth.mesial)), CavityWall::Mesial, CavityWall::Distal},
      {dot(across, vec(tooth.buccal)), CavityWall::Buccal, CavityWall::Lingual},
      {dot(across, vec(tooth.crown)), CavityWall::Occlusal, CavityWall::Gingival},
  }};
  size_t best = 0;
  for (size_t i = 1; i < sides.size(); ++i)
    if (std::abs(sides[i].component) > std::abs(sides[best].component)) best = i;
  const double side = std::abs(sides[best].component);
  if (along > side + eps || (break_ties && along >= side - eps)) {
    *out = CavityWall::OcclusalFloor;
    return true;
  }
  if (!break_ties) {
    if (along >= side - eps) return false;
    for (size_t i = 0; i < sides.size(); ++i)
      if (i != best && side - std::abs(sides[i].component) <= eps) return false;
  }
  *out = sides[best].component < 0 ? sides[best].facing_minus : sides[best].facing_plus;
  return true;
}

}  // namespace

CavityWall cavityWallOf(const Vec3& inward, const Vec3& own, const Vec3& axis, const ToothAxes& tooth) {
  assert(norm(inward) > 0 && norm(own) > 0);
  CavityWall wall = CavityWall::OcclusalFloor;
  if (wallOfDirection(inward, axis, tooth, false, &wall)) return wall;
  if (wallOfDirection(own, axis, tooth, false, &wall)) return wall;
  // A face exactly between walls whose own direction is too (a ceiling straight across the axis):
  // the first candidate in report order.
  wallOfDirection(inward, axis, tooth, true, &wall);
  return wall;
}

namespace {

// ---- 2. the box and its labels -------------------------------------------------------------------

constexpr uint8_t kTissue = 1;        // initial tissue
constexpr uint8_t kIdealKept = 2;     // initial tissue the ideal kept
constexpr uint8_t kStudentKept = 4;   // initial tissue the student kept

bool isTissue(Voxel v) {
  return kTissueIndexByCode[layout::voxelMaterial(v) & (DS_MATERIAL_COUNT - 1)] >= 0 && isHalfFull(v);
}
// The ideal cavity at the threshold: initial tissue whose ideal fill fell below half.
bool inIdealCavity(Voxel initial, Voxel ideal) { return isTissue(initial) && !isHalfFull(ideal); }

// A dense box [lo, hi) of the grid [voxels], x fastest.
struct Box {
  std::array<int64_t, 3> lo{}, hi{};
  int64_t size(int a) const { return hi[size_t(a)] - lo[size_t(a)]; }
  size_t count() const { return size_t(size(0)) * size_t(size(1)) * size_t(size(2)); }
  bool empty() const { return size(0) <= 0 || size(1) <= 0 || size(2) <= 0; }
  bool inside(int64_t x, int64_t y, int64_t z) const {
    return x >= lo[0] && y >= lo[1] && z >= lo[2] && x < hi[0] && y < hi[1] && z < hi[2];
  }
  size_t index(int64_t x, int64_t y, int64_t z) const {
    return size_t((x - lo[0]) + size(0) * ((y - lo[1]) + size(1) * (z - lo[2])));
  }
};

// The voxel bounds of the ideal cavity; empty when it has no voxel. Bricks equal in both volumes are
// skipped whole: the ideal removed nothing there.
Box idealCavityBounds(const BrickVolume& initial, const BrickVolume& ideal) {
  Box box;
  const int64_t dim = initial.dim();
  box.lo = {dim, dim, dim};
  box.hi = {0, 0, 0};
  const uint32_t bd = initial.brickDim();
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        const BrickCoord c{bx, by, bz};
        const BrickView vi = initial.brick(c), vk = ideal.brick(c);
        if (vi.sameVoxels(vk)) continue;
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          if (!inIdealCavity(vi.at(n), vk.at(n))) continue;
          const std::array<int64_t, 3> p{int64_t{bx} * DS_BRICK_DIM + (n & 7u), int64_t{by} * DS_BRICK_DIM + ((n >> 3) & 7u),
                                         int64_t{bz} * DS_BRICK_DIM + (n >> 6)};
          for (size_t a = 0; a < 3; ++a) {
            box.lo[a] = std::min(box.lo[a], p[a]);
            box.hi[a] = std::max(box.hi[a], p[a] + 1);
          }
        }
      }
  return box;
}

// Labels (kTissue | kIdealKept | kStudentKept) of every voxel of the box, read brick by brick.
std::vector<uint8_t> labelBox(const Box& box, const BrickVolume& initial, const BrickVolume& final_, const BrickVolume& ideal) {
  std::vector<uint8_t> labels(box.count(), 0);
  const std::array<int64_t, 3> blo{box.lo[0] >> DS_BRICK_LOG2, box.lo[1] >> DS_BRICK_LOG2, box.lo[2] >> DS_BRICK_LOG2};
  const std::array<int64_t, 3> bhi{(box.hi[0] - 1) >> DS_BRICK_LOG2, (box.hi[1] - 1) >> DS_BRICK_LOG2,
                                   (box.hi[2] - 1) >> DS_BRICK_LOG2};
  for (int64_t bz = blo[2]; bz <= bhi[2]; ++bz)
    for (int64_t by = blo[1]; by <= bhi[1]; ++by)
      for (int64_t bx = blo[0]; bx <= bhi[0]; ++bx) {
        const BrickCoord c{uint32_t(bx), uint32_t(by), uint32_t(bz)};
        const BrickView vi = initial.brick(c), vf = final_.brick(c), vk = ideal.brick(c);
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          const int64_t x = bx * DS_BRICK_DIM + (n & 7u), y = by * DS_BRICK_DIM + ((n >> 3) & 7u), z = bz * DS_BRICK_DIM + (n >> 6);
          if (!box.inside(x, y, z)) continue;
          const Voxel i = vi.at(n);
          if (!isTissue(i)) continue;
          uint8_t label = kTissue;
          if (isHalfFull(vk.at(n))) label |= kIdealKept;
          if (isHalfFull(vf.at(n)) && isHalfFull(i)) label |= kStudentKept;
          labels[box.index(x, y, z)] = label;
        }
      }
  return labels;
}

// ---- 3. exact squared distance transform -----------------------------------------------------------

constexpr int64_t kFar = std::numeric_limits<int32_t>::max();  // no feature [voxels^2]

// One line: d[q] = min over p of (q - p)^2 + f[p], where f[p] >= kFar is no feature (Felzenszwalb and
// Huttenlocher's lower envelope of parabolas). v and z are scratch of n and n + 1 entries.
void distanceLine(const int64_t* f, int64_t n, int64_t* d, int64_t* v, double* z) {
  int64_t k = -1;
  for (int64_t q = 0; q < n; ++q) {
    if (f[q] >= kFar) continue;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -std::numeric_limits<double>::infinity();
      z[1] = std::numeric_limits<double>::infinity();
      continue;
    }
    // The first parabola's z is -infinity, so the loop never pops it.
    double s = 0.0;
    for (;;) {
      const int64_t p = v[k];
      s = double((f[q] + q * q) - (f[p] + p * p)) / double(2 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) {
    std::fill(d, d + n, kFar);
    return;
  }
  k = 0;
  for (int64_t q = 0; q < n; ++q) {
    while (z[k + 1] < double(q)) ++k;
    d[q] = std::min(kFar, (q - v[k]) * (q - v[k]) + f[v[k]]);
  }
}

// Squared distance [voxels^2] from each voxel of the box to the nearest voxel where feature(label)
// holds, between centres; kFar when the box holds none. Exact within the box.
template <class Feature>
std::vector<int32_t> squaredDistance(const Box& box, const std::vector<uint8_t>& labels, Feature feature) {
  std::vector<int32_t> field(labels.size());
  for (size_t i = 0; i < labels.size(); ++i) field[i] = feature(labels[i]) ? 0 : int32_t(kFar);
  const auto longest = static_cast<size_t>(std::max({box.size(0), box.size(1), box.size(2)}));
  std::vector<int64_t> f(longest), d(longest), v(longest);
  std::vector<double> z(longest + 1);
  const std::array<int64_t, 3> stride{1, box.size(0), box.size(0) * box.size(1)};
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const int64_t n = box.size(axis);
    for (int64_t j2 = 0; j2 < box.size(a2); ++j2)
      for (int64_t j1 = 0; j1 < box.size(a1); ++j1) {
        const int64_t base = j1 * stride[size_t(a1)] + j2 * stride[size_t(a2)];
        for (int64_t q = 0; q < n; ++q) f[size_t(q)] = field[size_t(base + q * stride[size_t(axis)])];
        distanceLine(f.data(), n, d.data(), v.data(), z.data());
        for (int64_t q = 0; q < n; ++q) field[size_t(base + q * stride[size_t(axis)])] = int32_t(d[size_t(q)]);
      }
  }
  return field;
}

// ---- 4. measureSurfaceAgreement --------------------------------------------------------------------

struct Tally {
  uint64_t samples = 0, within = 0, beyond = 0, short_ = 0;
  double deviation_sum_mm = 0.0;
};

void fill(const Tally& t, double face_mm2, WallAgreement* out) {
  out->samples = t.samples;
  out->area_mm2 = double(t.samples) * face_mm2;
  out->within = t.within;
  out->beyond = t.beyond;
  out->short_ = t.short_;
  const double per = t.samples ? 100.0 / double(t.samples) : 0.0;
  out->within_percent = double(t.within) * per;
  out->beyond_percent = double(t.beyond) * per;
  out->short_percent = double(t.short_) * per;
  out->mean_deviation_mm = t.samples ? t.deviation_sum_mm / double(t.samples) : 0.0;
}

// The face's direction into the cavity: over the window around the face (2R voxels along the face's
// axis, 2R + 1 across), the cavity voxels' offsets minus the kept voxels'. Offsets are doubled so that
// the sums stay integers, and exact ties stay ties.
Vec3 inwardDirection(const Box& box, const std::vector<uint8_t>& labels, const std::array<int64_t, 3>& a, int axis) {
  std::array<int64_t, 3> lo{}, hi{};
  for (int k = 0; k < 3; ++k) {
    lo[size_t(k)] = a[size_t(k)] - kNormalRadius + (k == axis ? 1 : 0);
    hi[size_t(k)] = a[size_t(k)] + kNormalRadius;  // inclusive
  }
  std::array<int64_t, 3> sum{0, 0, 0};
  for (int64_t z = lo[2]; z <= hi[2]; ++z)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t x = lo[0]; x <= hi[0]; ++x) {
        if (!box.inside(x, y, z)) continue;
        const uint8_t l = labels[box.index(x, y, z)];
        if (!(l & kTissue)) continue;  // air beyond the tooth faces neither way
        const int64_t w = (l & kIdealKept) ? -1 : 1;
        const std::array<int64_t, 3> q{x, y, z};
        for (int k = 0; k < 3; ++k) {
          // 2 (q - p), p the face centre: a + 1/2 along the face's axis, a's centre across it.
          const int64_t doubled = 2 * (q[size_t(k)] - a[size_t(k)]) - (k == axis ? 1 : 0);
          sum[size_t(k)] += w * doubled;
        }
      }
  return {double(sum[0]), double(sum[1]), double(sum[2])};
}

}  // namespace

Result<SurfaceAgreement> measureSurfaceAgreement(const ToothVolume& initial, const ToothVolume& final_,
                                                 const ToothVolume& ideal, const Vec3& insertion_axis, double band_mm) {
  if (!(band_mm >= 0.0) || !std::isfinite(band_mm))
    return makeError("surface agreement", "the band must be a width of at least 0 mm");
  if (!(norm(insertion_axis) > 0.0)) return makeError("surface agreement", "the insertion axis is zero");
  if (Status st = checkSameFrame(initial, "initial", final_, "final"); !st) return st.error();
  if (Status st = checkSameFrame(initial, "initial", ideal, "ideal"); !st) return st.error();
  const Vec3 axis = normalized(insertion_axis);
  const double voxel_mm = initial.frame.voxel_mm;
  assert(voxel_mm > 0.0);

  SurfaceAgreement out;
  out.band_mm = band_mm;
  out.cap_mm = band_mm + kDeviationReachMm;
  out.voxel_mm = voxel_mm;
  for (size_t w = 0; w < kCavityWallCount; ++w) out.walls[w].wall = kWallNames[w];

  // 1. The box: the cavity, the kept voxels that face it, the normal's window, and room for the
  //    distances up to the cap (a feature farther than that from every face may lie outside).
  Box box = idealCavityBounds(initial.voxels, ideal.voxels);
  if (box.empty()) return out;
  const int64_t margin = int64_t(std::ceil(out.cap_mm / voxel_mm)) + kNormalRadius + 2;
  const int64_t dim = initial.voxels.dim();
  for (size_t a = 0; a < 3; ++a) {
    box.lo[a] = std::max<int64_t>(0, box.lo[a] - margin);
    box.hi[a] = std::min<int64_t>(dim, box.hi[a] + margin);
  }
  const std::vector<uint8_t> labels = labelBox(box, initial.voxels, final_.voxels, ideal.voxels);

  // 2. Distances: from each voxel the student cut (or air) to the tissue the student kept, and from
  //    each voxel the student kept to the nearest one it did not.
  const std::vector<int32_t> to_kept = squaredDistance(box, labels, [](uint8_t l) { return (l & kStudentKept) != 0; });
  const std::vector<int32_t> to_cut = squaredDistance(box, labels, [](uint8_t l) { return (l & kStudentKept) == 0; });
  const double cap_voxels = out.cap_mm / voxel_mm;
  const auto distance = [&](const std::vector<int32_t>& field, size_t i) {
    return std::min(std::sqrt(double(field[i])), cap_voxels);
  };

  // 3. Every face between an ideal cavity voxel and a kept one.
  std::array<Tally, kCavityWallCount> walls{};
  Tally all;
  const double band_voxels = band_mm / voxel_mm;
  const double tolerance = 1e-9 * std::max(1.0, band_voxels);  // a deviation of exactly the band is within
  for (int axis_index = 0; axis_index < 3; ++axis_index)
    for (int64_t z = box.lo[2]; z < box.hi[2]; ++z)
      for (int64_t y = box.lo[1]; y < box.hi[1]; ++y)
        for (int64_t x = box.lo[0]; x < box.hi[0]; ++x) {
          std::array<int64_t, 3> a{x, y, z}, b = a;
          b[size_t(axis_index)] += 1;
          if (!box.inside(b[0], b[1], b[2])) continue;
          const size_t ia = box.index(a[0], a[1], a[2]), ib = box.index(b[0], b[1], b[2]);
          const uint8_t la = labels[ia], lb = labels[ib];
          const bool cavity_a = (la & kTissue) && !(la & kIdealKept), cavity_b = (lb & kTissue) && !(lb & kIdealKept);
          size_t cavity = 0, kept = 0;
          Vec3 own{0, 0, 0};
          if (cavity_a && (lb & kIdealKept)) {
            cavity = ia;
            kept = ib;
            own[axis_index] = -1;  // from the kept voxel toward the cavity
          } else if (cavity_b && (la & kIdealKept)) {
            cavity = ib;
            kept = ia;
            own[axis_index] = 1;
          } else {
            continue;
          }
          // The deviation [voxels]: beyond where the student cut the kept voxel, short where it kept the cavity's.
          double deviation = 0.0;
          if (!(labels[kept] & kStudentKept)) deviation += distance(to_kept, kept);
          if (labels[cavity] & kStudentKept) deviation -= distance(to_cut, cavity);
          const Vec3 inward = inwardDirection(box, labels, a, axis_index);
          const CavityWall wall = cavityWallOf(norm(inward) > 0 ? inward : own, own, axis, initial.frame.tooth);
          uint32_t mark = kMarkWithin;
          Tally& t = walls[size_t(wall)];
          for (Tally* tally : {&t, &all}) {
            ++tally->samples;
            tally->deviation_sum_mm += deviation * voxel_mm;
          }
          if (deviation > band_voxels + tolerance) {
            ++t.beyond;
            ++all.beyond;
            mark = kMarkBeyond;
          } else if (deviation < -band_voxels - tolerance) {
            ++t.short_;
            ++all.short_;
            mark = kMarkShort;
          } else {
            ++t.within;
            ++all.within;
          }
          const std::array<int64_t, 3>& k = cavity == ia ? b : a;
          out.marks.add(uint32_t(k[0]), uint32_t(k[1]), uint32_t(k[2]), mark);
        }

  const double face_mm2 = voxel_mm * voxel_mm;
  WallAgreement total;
  fill(all, face_mm2, &total);
  out.samples = total.samples;
  out.area_mm2 = total.area_mm2;
  out.within = total.within;
  out.beyond = total.beyond;
  out.short_ = total.short_;
  out.within_percent = total.within_percent;
  out.beyond_percent = total.beyond_percent;
  out.short_percent = total.short_percent;
  out.mean_deviation_mm = total.mean_deviation_mm;
  for (size_t w = 0; w < kCavityWallCount; ++w) fill(walls[w], face_mm2, &out.walls[w]);
  return out;
}

// ---- 5. JSON -------------------------------------------------------------------------------------

namespace {

nlohmann::ordered_json sharesJson(uint64_t samples, double area_mm2, double within, double beyond, double short_,
                                  double mean_deviation_mm) {
  return {{"samples", samples},
          {"area_mm2", area_mm2},
          {"within_percent", within},
          {"beyond_percent", beyond},
          {"short_percent", short_},
          {"mean_deviation_mm", mean_deviation_mm}};
}

}  // namespace

nlohmann::ordered_json surfaceAgreementJson(const SurfaceAgreement& s) {
  nlohmann::ordered_json j = {{"band_mm", s.band_mm}};
  const nlohmann::ordered_json whole =
      sharesJson(s.samples, s.area_mm2, s.within_percent, s.beyond_percent, s.short_percent, s.mean_deviation_mm);
  for (const auto& item : whole.items()) j[item.key()] = item.value();
  nlohmann::ordered_json walls = nlohmann::ordered_json::object();
  for (size_t w = 0; w < kCavityWallCount; ++w) {
    const WallAgreement& a = s.walls[w];
    if (w >= kAlwaysReportedWalls && a.samples == 0) continue;
    walls[kWallNames[w]] = sharesJson(a.samples, a.area_mm2, a.within_percent, a.beyond_percent, a.short_percent,
                                      a.mean_deviation_mm);
  }
  j["walls"] = std::move(walls);
  return j;
}

}  // namespace dentsim
