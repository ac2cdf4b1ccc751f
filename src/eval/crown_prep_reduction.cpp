// The crown preparation's reduction measures: surface samples of the original, normals, rays to the prepared tooth, per-region figures.
#include "eval/crown_prep_reduction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/percentile.h"
#include "volume/brick_layout.h"
#include "volume/tissue_table.h"
#include "volume/half_fill.h"

namespace dentsim {
namespace {

// Strictly within 45 degrees; the tolerance keeps exact-45 normals (edges, corners) out of every region.
const double kCos45 = std::sqrt(0.5) + 1e-6;
// Ray step [voxels]: a power of two, so that steps along a grid axis land on exact centres and faces.
constexpr double kStep = 0.125;
// Band comparisons forgive rounding in voxel_mm products, so a reduction exactly at a bound is in band.
constexpr double kBandEps = 1e-9;

// The flags of the reduction's voxel box.
constexpr uint8_t kOriginal = 1;  // tooth in the original
constexpr uint8_t kPrepared = 2;  // tooth in the prepared tooth

struct Masks {
  CrownVoxelBox box;
  bool orig(int32_t x, int32_t y, int32_t z) const { return box.at(x, y, z) & kOriginal; }
  bool prep(int32_t x, int32_t y, int32_t z) const { return box.at(x, y, z) & kPrepared; }
};

// The voxel holding coordinate c on a ray going `dir` along that axis: a point on a face between two
// voxels counts in the one ahead, so a ray reaches a voxel at the same step whichever way it runs.
int32_t roundAlong(double c, double dir) {
  return int32_t(dir < 0 ? std::ceil(c - 0.5) : std::floor(c + 0.5));
}

// A voxel centre's height along `axis` from the grid origin [voxels].
double centreHeight(int32_t x, int32_t y, int32_t z, const Vec3& axis) {
  return dot(Vec3(x + 0.5, y + 0.5, z + 0.5), axis);
}

// The reduction [voxels] along -normal from (x,y,z), or a negative value when the ray leaves the
// original tooth or goes down to the margin (a centre height along `axis`, in voxels, at or under
// `margin`) without meeting the prepared one. `hit` gets the prepared voxel met (x,y,z itself when
// it is still prepared).
double rayReduction(const Masks& m, int32_t x, int32_t y, int32_t z, const Vec3& inward, const Vec3& axis,
                    double margin, std::array<int32_t, 3>& hit) {
  hit = {x, y, z};
  if (m.prep(x, y, z)) return 0;
  int32_t last[3] = {x, y, z};
  for (int k = 1;; ++k) {
    const double t = k * kStep;
    const int32_t qx = roundAlong(x + t * inward.x, inward.x);
    const int32_t qy = roundAlong(y + t * inward.y, inward.y);
    const int32_t qz = roundAlong(z + t * inward.z, inward.z);
    if (qx == last[0] && qy == last[1] && qz == last[2]) continue;  // still in the voxel just read
    last[0] = qx, last[1] = qy, last[2] = qz;
    if (centreHeight(qx, qy, qz, axis) <= margin) return -1;
    if (m.prep(qx, qy, qz)) {
      hit = {qx, qy, qz};
      return t + 0.5;  // outer face to outer face: half a voxel beyond each centre
    }
    if (!m.orig(qx, qy, qz)) return -1;
  }
}

// A surface voxel's outward normal: the sum of the offsets of its 26 neighbours that are not
// `inside`, normalized; zero for a sheet one voxel thin, which has no outward side.
template <class Inside>
Vec3 outwardNormal(const Inside& inside, int32_t x, int32_t y, int32_t z) {
  Vec3 sum;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (!inside(x + dx, y + dy, z + dz)) sum += Vec3(dx, dy, dz);
  return norm(sum) == 0 ? Vec3{} : normalized(sum);
}

// Sorts a key list (so z, y, x order) and drops repeats.
void sortUnique(std::vector<uint64_t>& keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

struct Accum {
  int samples = 0, under = 0, over = 0;
  double sum = 0, min = std::numeric_limits<double>::infinity(), max = 0;
  std::vector<double> readings;  // [mm], for the median

  ReductionStats stats() const {
    ReductionStats s;
    if (samples == 0) return s;
    s.samples = samples;
    s.mean_mm = sum / samples;
    s.median_mm = percentile(readings, 50.0);
    s.min_mm = min;
    s.max_mm = max;
    s.under_share = double(under) / samples;
    s.over_share = double(over) / samples;
    return s;
  }
};

}  // namespace

Status checkCrownTeeth(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm, const std::string& where) {
  if (original.level() != prepared.level())
    return makeError(where, "the original (level " + std::to_string(original.level()) + ") and the prepared tooth (level " +
                                std::to_string(prepared.level()) + ") are on different grids");
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm)) return makeError(where, "the voxel size must be > 0 mm");
  return Ok{};
}

Result<CrownFrame> crownFrame(const Vec3& insertion_axis, const Vec3& mesial, const std::string& where) {
  if (!finite(insertion_axis) || norm(insertion_axis) == 0) return makeError(where, "the insertion axis is zero or not finite");
  CrownFrame f;
  f.axis = normalized(insertion_axis);
  if (!finite(mesial)) return makeError(where, "the mesial direction is not finite");
  const Vec3 across = mesial - f.axis * dot(mesial, f.axis);
  if (norm(across) < 1e-6 * std::max(1.0, norm(mesial)))
    return makeError(where, "the mesial direction is zero or along the insertion axis");
  f.mesial = normalized(across);
  f.buccal = cross(f.axis, f.mesial);
  return f;
}

CrownVoxelBox crownVoxelBox(const BrickVolume& a, const BrickVolume* b) {
  BrickBox bricks;
  auto grow = [&](const BrickView& v) {
    if (v.uniform) {
      if (!isToothTissue(voxelMaterial(v.value))) return;
    } else if (std::none_of(v.voxels, v.voxels + DS_BRICK_VOXELS, [](Voxel x) { return isToothTissue(voxelMaterial(x)); })) {
      return;
    }
    bricks.lo = {std::min(bricks.lo.x, v.coord.x), std::min(bricks.lo.y, v.coord.y), std::min(bricks.lo.z, v.coord.z)};
    bricks.hi = {std::max(bricks.hi.x, v.coord.x), std::max(bricks.hi.y, v.coord.y), std::max(bricks.hi.z, v.coord.z)};
  };
  a.forEachBrick(grow);
  if (b != nullptr) b->forEachBrick(grow);
  CrownVoxelBox box;
  if (bricks.empty()) return box;
  const int32_t dim = int32_t(a.dim());
  const uint32_t blo[3] = {bricks.lo.x, bricks.lo.y, bricks.lo.z};
  const uint32_t bhi[3] = {bricks.hi.x, bricks.hi.y, bricks.hi.z};
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = std::max(0, int32_t(blo[k] * DS_BRICK_DIM) - 1);
    box.n[k] = std::min(dim, int32_t((bhi[k] + 1) * DS_BRICK_DIM) + 1) - box.lo[k];
  }
  box.bits.assign(size_t(box.n[0]) * size_t(box.n[1]) * size_t(box.n[2]), 0);
  return box;
}

void markTooth(CrownVoxelBox& box, const BrickVolume& v, uint8_t tooth_bit, uint8_t enamel_bit) {
  if (box.empty()) return;
  const int32_t d = int32_t(DS_BRICK_DIM);
  int32_t blo[3], bhi[3];
  for (int k = 0; k < 3; ++k) {
    blo[k] = box.lo[k] / d;
    bhi[k] = std::min(int32_t(v.brickDim()) - 1, (box.lo[k] + box.n[k] - 1) / d);
  }
  for (int32_t bz = blo[2]; bz <= bhi[2]; ++bz)
    for (int32_t by = blo[1]; by <= bhi[1]; ++by)
      for (int32_t bx = blo[0]; bx <= bhi[0]; ++bx) {
        const BrickView b = v.brick({uint32_t(bx), uint32_t(by), uint32_t(bz)});
        if (b.uniform && !isSolidTooth(b.value)) continue;
        if (box.inBox(bx * d, by * d, bz * d) && box.inBox(bx * d + d - 1, by * d + d - 1, bz * d + d - 1)) {
          // The whole brick lies in the box (all but the padding's): row by row, no bounds to test.
          for (int32_t z = 0; z < d; ++z)
            for (int32_t y = 0; y < d; ++y) {
              uint8_t* row = &box.bits[box.index(bx * d, by * d + y, bz * d + z)];
              for (int32_t x = 0; x < d; ++x) {
                const Voxel here = b.at(layout::brickCoordToOffset(uint32_t(x), uint32_t(y), uint32_t(z)));
                if (!isSolidTooth(here)) continue;
                const Material m = voxelMaterial(here);
                row[x] = uint8_t(row[x] | tooth_bit | (m == Material::Enamel ? enamel_bit : 0));
              }
            }
          continue;
        }
        for (int32_t z = 0; z < d; ++z)
          for (int32_t y = 0; y < d; ++y)
            for (int32_t x = 0; x < d; ++x) {
              const int32_t gx = bx * d + x, gy = by * d + y, gz = bz * d + z;
              if (!box.inBox(gx, gy, gz)) continue;
              const Voxel here = b.at(layout::brickCoordToOffset(uint32_t(x), uint32_t(y), uint32_t(z)));
              if (!isSolidTooth(here)) continue;
              const Material m = voxelMaterial(here);
              uint8_t& f = box.bits[box.index(gx, gy, gz)];
              f |= tooth_bit;
              if (m == Material::Enamel) f |= enamel_bit;
            }
      }
}

Result<CrownPrepReduction> measureReduction(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                                            const Vec3& insertion_axis, const Vec3& mesial, double margin_height_mm,
                                            const ReductionBands& bands) {
  const std::string where = "crown reduction";
  if (Status st = checkCrownTeeth(original, prepared, voxel_mm, where); !st) return st.error();
  const Result<CrownFrame> frame = crownFrame(insertion_axis, mesial, where);
  if (!frame) return frame.error();
  const Vec3 axis = frame->axis;
  if (!(bands.occlusal_lo <= bands.occlusal_hi) || !(bands.axial_lo <= bands.axial_hi))
    return makeError(where, "a target band's lo is above its hi");

  Masks m;
  m.box = crownVoxelBox(original, &prepared);
  markTooth(m.box, original, kOriginal);
  markTooth(m.box, prepared, kPrepared);
  bool any_original = false, any_prepared = false;
  for (uint8_t f : m.box.bits) any_original = any_original || (f & kOriginal), any_prepared = any_prepared || (f & kPrepared);
  if (!any_original) return makeError(where, "the original holds no tooth");
  if (!any_prepared) return makeError(where, "the prepared tooth holds no tooth");

  // Heights are along the axis from the grid origin (as crown_prep_taper.h), in voxels until compared.
  const double margin_voxels = margin_height_mm / voxel_mm;

  const std::array<Vec3, 4> wall_dirs = {frame->mesial, -frame->mesial, frame->buccal, -frame->buccal};

  CrownPrepReduction out;
  Accum occlusal;
  std::array<Accum, 4> walls;
  bool any_above = false;
  const CrownVoxelBox& box = m.box;
  for (int32_t z = box.lo[2]; z < box.lo[2] + box.n[2]; ++z)
    for (int32_t y = box.lo[1]; y < box.lo[1] + box.n[1]; ++y)
      for (int32_t x = box.lo[0]; x < box.lo[0] + box.n[0]; ++x) {
        if (!(box.bits[box.index(x, y, z)] & kOriginal)) continue;
        if (box.faceNeighboursAnd(x, y, z) & kOriginal) continue;  // inside: not a sample
        if (centreHeight(x, y, z, axis) <= margin_voxels) continue;
        any_above = true;
        const Vec3 normal = outwardNormal([&](int32_t a, int32_t b, int32_t c) { return m.orig(a, b, c); }, x, y, z);
        if (norm(normal) == 0) continue;  // a sheet one voxel thin: no side is outward

        Accum* acc = nullptr;
        double lo = 0, hi = 0;
        if (dot(normal, axis) > kCos45) {
          acc = &occlusal;
          lo = bands.occlusal_lo;
          hi = bands.occlusal_hi;
        } else {
          for (size_t w = 0; w < 4; ++w)
            if (dot(normal, wall_dirs[w]) > kCos45) {
              acc = &walls[w];
              lo = bands.axial_lo;
              hi = bands.axial_hi;
            }
        }
        if (acc == nullptr) continue;
        std::array<int32_t, 3> hit;
        const double voxels = rayReduction(m, x, y, z, -normal, axis, margin_voxels, hit);
        // An occlusal gauge must land on the table: a ray that meets the preparation on an axial
        // wall (the hit's normal in a wall's region, by the rule the samples are sorted by) crossed
        // the occlusal-axial corner that the walls took off whole, and reads the wall.
        bool on_wall = false;
        if (acc == &occlusal && voxels > 0) {
          const Vec3 hit_normal =
              outwardNormal([&](int32_t a, int32_t b, int32_t c) { return m.prep(a, b, c); }, hit[0], hit[1], hit[2]);
          for (const Vec3& d : wall_dirs) on_wall = on_wall || dot(hit_normal, d) > kCos45;
        }
        if (voxels < 0 || on_wall) {
          ++out.unreached;
          continue;
        }
        const double mm = voxels * voxel_mm;
        ++acc->samples;
        acc->sum += mm;
        acc->readings.push_back(mm);
        acc->min = std::min(acc->min, mm);
        acc->max = std::max(acc->max, mm);
        const uint64_t key = reductionVoxelKey(uint32_t(x), uint32_t(y), uint32_t(z));
        const uint64_t hit_key = reductionVoxelKey(uint32_t(hit[0]), uint32_t(hit[1]), uint32_t(hit[2]));
        if (mm < lo - kBandEps) {
          ++acc->under;
          out.under_voxels.push_back(key);
          out.prepared_under.push_back(hit_key);
        } else if (mm > hi + kBandEps) {
          ++acc->over;
          out.over_voxels.push_back(key);
          out.prepared_over.push_back(hit_key);
        } else {
          out.prepared_within.push_back(hit_key);
        }
      }
  if (!any_above)
    return makeError(where, "no surface of the original lies above the margin height " + std::to_string(margin_height_mm) + " mm");

  // Several samples' rays may meet one prepared voxel (at an inside corner); each list names it once.
  sortUnique(out.prepared_under);
  sortUnique(out.prepared_within);
  sortUnique(out.prepared_over);
  out.occlusal = occlusal.stats();
  for (size_t w = 0; w < 4; ++w) out.axial[w] = walls[w].stats();
  return out;
}

}  // namespace dentsim
