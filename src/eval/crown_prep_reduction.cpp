// The crown preparation's reduction measures: surface samples of the original, normals, rays to the prepared tooth, per-region figures.
#include "eval/crown_prep_reduction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

// Strictly within 45 degrees; the tolerance keeps exact-45 normals (edges, corners) out of every region.
const double kCos45 = std::sqrt(0.5) + 1e-6;
// Ray step [voxels]: a power of two, so that steps along a grid axis land on exact centres and faces.
constexpr double kStep = 0.125;
// Band comparisons forgive rounding in voxel_mm products, so a reduction exactly at a bound is in band.
constexpr double kBandEps = 1e-9;

// Both tooth masks over the tissue's bounding box padded by one voxel (a dense copy: the rays read
// each voxel many times, and BrickVolume::voxel walks the tree each time).
struct Masks {
  int32_t lo[3] = {0, 0, 0};
  int32_t n[3] = {0, 0, 0};
  std::vector<uint8_t> original, prepared;

  bool inBox(int32_t x, int32_t y, int32_t z) const {
    return x >= lo[0] && y >= lo[1] && z >= lo[2] && x < lo[0] + n[0] && y < lo[1] + n[1] && z < lo[2] + n[2];
  }
  size_t index(int32_t x, int32_t y, int32_t z) const {
    return (size_t(z - lo[2]) * size_t(n[1]) + size_t(y - lo[1])) * size_t(n[0]) + size_t(x - lo[0]);
  }
  bool orig(int32_t x, int32_t y, int32_t z) const { return inBox(x, y, z) && original[index(x, y, z)]; }
  bool prep(int32_t x, int32_t y, int32_t z) const { return inBox(x, y, z) && prepared[index(x, y, z)]; }
};

Masks buildMasks(const BrickVolume& original, const BrickVolume& prepared, const BrickBox& box) {
  Masks m;
  const int32_t dim = int32_t(original.dim());
  const uint32_t blo[3] = {box.lo.x, box.lo.y, box.lo.z};
  const uint32_t bhi[3] = {box.hi.x, box.hi.y, box.hi.z};
  for (int a = 0; a < 3; ++a) {
    m.lo[a] = std::max(0, int32_t(blo[a] * DS_BRICK_DIM) - 1);
    const int32_t hi = std::min(dim, int32_t((bhi[a] + 1) * DS_BRICK_DIM) + 1);
    m.n[a] = hi - m.lo[a];
  }
  const size_t count = size_t(m.n[0]) * size_t(m.n[1]) * size_t(m.n[2]);
  m.original.assign(count, 0);
  m.prepared.assign(count, 0);
  for (int32_t z = m.lo[2]; z < m.lo[2] + m.n[2]; ++z)
    for (int32_t y = m.lo[1]; y < m.lo[1] + m.n[1]; ++y)
      for (int32_t x = m.lo[0]; x < m.lo[0] + m.n[0]; ++x) {
        const size_t i = m.index(x, y, z);
        m.original[i] = isToothTissue(voxelMaterial(original.voxel(uint32_t(x), uint32_t(y), uint32_t(z)))) ? 1 : 0;
        m.prepared[i] = isToothTissue(voxelMaterial(prepared.voxel(uint32_t(x), uint32_t(y), uint32_t(z)))) ? 1 : 0;
      }
  return m;
}

BrickBox unite(const BrickBox& a, const BrickBox& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  BrickBox u;
  u.lo = {std::min(a.lo.x, b.lo.x), std::min(a.lo.y, b.lo.y), std::min(a.lo.z, b.lo.z)};
  u.hi = {std::max(a.hi.x, b.hi.x), std::max(a.hi.y, b.hi.y), std::max(a.hi.z, b.hi.z)};
  return u;
}

// The voxel holding coordinate c on a ray going `dir` along that axis: a point on a face between two
// voxels counts in the one ahead, so a ray reaches a voxel at the same step whichever way it runs.
int32_t roundAlong(double c, double dir) {
  return int32_t(dir < 0 ? std::ceil(c - 0.5) : std::floor(c + 0.5));
}

// The reduction [voxels] along -normal from (x,y,z), or a negative value when the ray leaves the
// original tooth or goes down to the margin (height along `axis` above `base`, in voxels, at or
// under `margin`) without meeting the prepared one.
double rayReduction(const Masks& m, int32_t x, int32_t y, int32_t z, const Vec3& inward, const Vec3& axis,
                    double base, double margin) {
  if (m.prep(x, y, z)) return 0;
  for (int k = 1;; ++k) {
    const double t = k * kStep;
    const int32_t qx = roundAlong(x + t * inward.x, inward.x);
    const int32_t qy = roundAlong(y + t * inward.y, inward.y);
    const int32_t qz = roundAlong(z + t * inward.z, inward.z);
    if (dot(Vec3(qx, qy, qz), axis) - base <= margin) return -1;
    if (m.prep(qx, qy, qz)) return t + 0.5;  // outer face to outer face: half a voxel beyond each centre
    if (!m.orig(qx, qy, qz)) return -1;
  }
}

struct Accum {
  int samples = 0, under = 0, over = 0;
  double sum = 0, min = std::numeric_limits<double>::infinity(), max = 0;

  ReductionStats stats() const {
    ReductionStats s;
    if (samples == 0) return s;
    s.samples = samples;
    s.mean_mm = sum / samples;
    s.min_mm = min;
    s.max_mm = max;
    s.under_share = double(under) / samples;
    s.over_share = double(over) / samples;
    return s;
  }
};

}  // namespace

Result<CrownPrepReduction> measureReduction(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                                            const Vec3& insertion_axis, const Vec3& mesial, double margin_height_mm,
                                            const ReductionBands& bands) {
  const std::string where = "crown reduction";
  if (original.level() != prepared.level())
    return makeError(where, "the original (level " + std::to_string(original.level()) + ") and the prepared tooth (level " +
                                std::to_string(prepared.level()) + ") are on different grids");
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm)) return makeError(where, "the voxel size must be > 0 mm");
  if (!finite(insertion_axis) || norm(insertion_axis) == 0) return makeError(where, "the insertion axis is zero");
  const Vec3 axis = normalized(insertion_axis);
  if (!finite(mesial)) return makeError(where, "the mesial direction is not finite");
  const Vec3 mesial_dir = normalized(mesial - axis * dot(mesial, axis));
  if (norm(mesial - axis * dot(mesial, axis)) < 1e-6 * std::max(1.0, norm(mesial)))
    return makeError(where, "the mesial direction is zero or along the insertion axis");
  if (!(bands.occlusal_lo <= bands.occlusal_hi) || !(bands.axial_lo <= bands.axial_hi))
    return makeError(where, "a target band's lo is above its hi");

  const BrickBox orig_box = tissueBricks(original);
  const BrickBox prep_box = tissueBricks(prepared);
  if (orig_box.empty()) return makeError(where, "the original holds no tooth");
  if (prep_box.empty()) return makeError(where, "the prepared tooth holds no tooth");
  const Masks m = buildMasks(original, prepared, unite(orig_box, prep_box));
  if (std::find(m.original.begin(), m.original.end(), 1) == m.original.end())
    return makeError(where, "the original holds no tooth");
  if (std::find(m.prepared.begin(), m.prepared.end(), 1) == m.prepared.end())
    return makeError(where, "the prepared tooth holds no tooth");

  // Heights are along the axis above the original's lowest voxel centre, in voxels until compared.
  double base = std::numeric_limits<double>::infinity();
  for (int32_t z = m.lo[2]; z < m.lo[2] + m.n[2]; ++z)
    for (int32_t y = m.lo[1]; y < m.lo[1] + m.n[1]; ++y)
      for (int32_t x = m.lo[0]; x < m.lo[0] + m.n[0]; ++x)
        if (m.original[m.index(x, y, z)]) base = std::min(base, dot(Vec3(x, y, z), axis));

  const Vec3 buccal_dir = cross(axis, mesial_dir);
  const std::array<Vec3, 4> wall_dirs = {mesial_dir, -mesial_dir, buccal_dir, -buccal_dir};

  CrownPrepReduction out;
  Accum occlusal;
  std::array<Accum, 4> walls;
  bool any_above = false;
  static constexpr int kFace[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int32_t z = m.lo[2]; z < m.lo[2] + m.n[2]; ++z)
    for (int32_t y = m.lo[1]; y < m.lo[1] + m.n[1]; ++y)
      for (int32_t x = m.lo[0]; x < m.lo[0] + m.n[0]; ++x) {
        if (!m.original[m.index(x, y, z)]) continue;
        bool surface = false;
        for (const auto& f : kFace) surface = surface || !m.orig(x + f[0], y + f[1], z + f[2]);
        if (!surface) continue;
        if ((dot(Vec3(x, y, z), axis) - base) * voxel_mm <= margin_height_mm) continue;
        any_above = true;
        Vec3 sum;
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (!m.orig(x + dx, y + dy, z + dz)) sum += Vec3(dx, dy, dz);
        const Vec3 normal = normalized(sum);
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
        const double voxels = rayReduction(m, x, y, z, -normal, axis, base, margin_height_mm / voxel_mm);
        if (voxels < 0) {
          ++out.unreached;
          continue;
        }
        const double mm = voxels * voxel_mm;
        ++acc->samples;
        acc->sum += mm;
        acc->min = std::min(acc->min, mm);
        acc->max = std::max(acc->max, mm);
        const uint64_t key = reductionVoxelKey(uint32_t(x), uint32_t(y), uint32_t(z));
        if (mm < lo - kBandEps) {
          ++acc->under;
          out.under_voxels.push_back(key);
        } else if (mm > hi + kBandEps) {
          ++acc->over;
          out.over_voxels.push_back(key);
        }
      }
  if (!any_above)
    return makeError(where, "no surface of the original lies above the margin height " + std::to_string(margin_height_mm) + " mm");

  out.occlusal = occlusal.stats();
  for (size_t w = 0; w < 4; ++w) out.axial[w] = walls[w].stats();
  return out;
}

}  // namespace dentsim
