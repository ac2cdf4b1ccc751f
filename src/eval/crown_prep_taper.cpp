// The crown preparation's taper measures: section profiles through the insertion axis, wall lines fitted by least squares, height and width.
#include "eval/crown_prep_taper.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "volume/brick_layout.h"
#include "volume/tissue_table.h"
#include "volume/half_fill.h"

namespace dentsim {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// Half the slab around a plane [voxels]: a diagonal plane passes between voxel centres, so half a
// voxel would leave bins empty; 0.75 keeps one or two centres per bin while the section's extent
// at 0.75 voxel off a wall's plane differs from it by far less than a voxel.
constexpr double kSlabHalfVoxels = 0.75;

// Calls fn(centre [mm]) for every tooth voxel, skipping tiles that hold no tooth.
template <class Fn>
void forEachToothVoxel(const BrickVolume& volume, double voxel_mm, Fn&& fn) {
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && !isSolidTooth(b.value)) return;
    for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
      for (uint32_t y = 0; y < DS_BRICK_DIM; ++y)
        for (uint32_t x = 0; x < DS_BRICK_DIM; ++x) {
          if (!isSolidTooth(b.at(layout::brickCoordToOffset(x, y, z)))) continue;
          fn(Vec3{(b.coord.x * DS_BRICK_DIM + x + 0.5) * voxel_mm, (b.coord.y * DS_BRICK_DIM + y + 0.5) * voxel_mm,
                  (b.coord.z * DS_BRICK_DIM + z + 0.5) * voxel_mm});
        }
  });
}

// One plane's profile: per height bin, the extreme in-plane coordinates of the slab's tooth voxels.
struct Profile {
  std::vector<double> lo, hi;  // (bins) min and max of dot(centre, direction) [mm]; +inf/-inf when empty
};

// Least-squares slope of u over h [mm/mm]; needs n >= 2 distinct heights.
double fitSlope(const std::vector<double>& h, const std::vector<double>& u) {
  const double n = double(h.size());
  double hm = 0, um = 0;
  for (size_t i = 0; i < h.size(); ++i) hm += h[i], um += u[i];
  hm /= n, um /= n;
  double shu = 0, shh = 0;
  for (size_t i = 0; i < h.size(); ++i) shu += (h[i] - hm) * (u[i] - um), shh += (h[i] - hm) * (h[i] - hm);
  assert(shh > 0);
  return shu / shh;
}

}  // namespace

Result<CrownPrepShape> measurePrepShape(const BrickVolume& volume, double voxel_mm, const Vec3& insertion_axis,
                                        const Vec3& mesial, double margin_height_mm) {
  assert(voxel_mm > 0);
  // 1. The frame: the axis, mesial across it, buccolingual across both.
  if (!finite(insertion_axis) || norm(insertion_axis) == 0) return Error{"crown preparation: the insertion axis is zero or not finite"};
  const Vec3 a = normalized(insertion_axis);
  const Vec3 m_across = mesial - dot(mesial, a) * a;
  if (!finite(mesial) || norm(m_across) < 1e-6 * std::max(1.0, norm(mesial)))
    return Error{"crown preparation: the mesial direction lies along the insertion axis"};
  const Vec3 m = normalized(m_across);
  const Vec3 b = cross(a, m);
  CrownPrepShape shape;
  const double r2 = std::sqrt(0.5);
  const char* names[4] = {"mesiodistal", "buccolingual", "diagonal+45", "diagonal-45"};
  const Vec3 dirs[4] = {m, b, r2 * (m + b), r2 * (m - b)};
  for (int k = 0; k < 4; ++k) shape.planes[size_t(k)].name = names[k], shape.planes[size_t(k)].direction = dirs[k];

  // 2. The tooth's extent along the axis.
  double h_min = std::numeric_limits<double>::infinity(), h_max = -h_min;
  forEachToothVoxel(volume, voxel_mm, [&](const Vec3& p) {
    const double h = dot(p, a);
    h_min = std::min(h_min, h), h_max = std::max(h_max, h);
  });
  if (!(h_min <= h_max)) return Error{"crown preparation: the volume holds no tooth voxels"};
  const double half = 0.5 * voxel_mm;
  // The faces' heights are sums of rounded centres: a margin on the bottom face may read a hair below.
  const double eps = 1e-6 * voxel_mm;
  if (margin_height_mm < h_min - half - eps || margin_height_mm >= h_max + half - eps)
    return Error{"crown preparation: the margin height " + std::to_string(margin_height_mm) +
                 " mm is outside the tooth (" + std::to_string(h_min - half) + " to " + std::to_string(h_max + half) +
                 " mm along the axis)"};
  // Bins one voxel tall, centred on the lowest centre's height, so a grid-aligned axis puts each
  // layer of voxels in its own bin at its exact height.
  auto binOf = [&](double h) { return size_t(std::lround((h - h_min) / voxel_mm)); };
  auto binHeight = [&](size_t i) { return h_min + double(i) * voxel_mm; };
  const size_t bins = binOf(h_max) + 1;
  // The band: bins whose height lies in [margin, margin + band]. The margin's bin is its first.
  size_t band_lo = 0;
  while (band_lo < bins && binHeight(band_lo) < margin_height_mm - eps) ++band_lo;
  size_t band_hi = band_lo;  // one past the last
  while (band_hi < bins && binHeight(band_hi) <= margin_height_mm + kTaperBandMm + eps) ++band_hi;

  // 3. The planes pass through the centroid of the band's voxels.
  Vec3 sum{};
  double count = 0;
  forEachToothVoxel(volume, voxel_mm, [&](const Vec3& p) {
    const size_t i = binOf(dot(p, a));
    if (i >= band_lo && i < band_hi) sum += p, count += 1;
  });
  if (count == 0) return Error{"crown preparation: no tooth voxels in the band above the margin"};
  const Vec3 centre = sum / count;

  // 4. Each plane's profile within its slab.
  std::array<Profile, 4> prof;
  Vec3 normals[4];
  double offsets[4];
  for (size_t k = 0; k < 4; ++k) {
    prof[k].lo.assign(bins, std::numeric_limits<double>::infinity());
    prof[k].hi.assign(bins, -std::numeric_limits<double>::infinity());
    normals[k] = cross(a, dirs[k]);
    offsets[k] = dot(centre, normals[k]);
  }
  const double slab = kSlabHalfVoxels * voxel_mm;
  forEachToothVoxel(volume, voxel_mm, [&](const Vec3& p) {
    const size_t i = binOf(dot(p, a));
    for (size_t k = 0; k < 4; ++k) {
      if (std::abs(dot(p, normals[k]) - offsets[k]) > slab) continue;
      const double u = dot(p, dirs[k]);
      prof[k].lo[i] = std::min(prof[k].lo[i], u), prof[k].hi[i] = std::max(prof[k].hi[i], u);
    }
  });

  // 5. Each wall's line over the band: distance from the centre line against height.
  for (size_t k = 0; k < 4; ++k) {
    TaperPlane& plane = shape.planes[k];
    const double u0 = dot(centre, dirs[k]);
    for (int side = 0; side < 2; ++side) {
      std::vector<double> hs, ds;
      for (size_t i = band_lo; i < band_hi; ++i) {
        if (prof[k].lo[i] > prof[k].hi[i]) continue;
        hs.push_back(binHeight(i));
        ds.push_back(side == 0 ? prof[k].hi[i] - u0 : u0 - prof[k].lo[i]);
      }
      if (int(hs.size()) < kMinWallPoints)
        return Error{std::string("crown preparation: ") + plane.name + " plane: " + std::to_string(hs.size()) +
                     " heights on a wall in the band above the margin, fewer than " + std::to_string(kMinWallPoints)};
      // The finish line's rounding (a chamfer's or shoulder's foot) runs outward at the band's
      // bottom; the axial wall is what stays on the upper half's line. Walk down from the upper
      // half while the profile keeps within kWallDepartureVoxels of that line.
      size_t first = hs.size() / 2;
      {
        const std::vector<double> uh(hs.begin() + long(first), hs.end()), ud(ds.begin() + long(first), ds.end());
        const double slope = fitSlope(uh, ud);
        double hm = 0, dm = 0;
        for (size_t j = 0; j < uh.size(); ++j) hm += uh[j], dm += ud[j];
        hm /= double(uh.size()), dm /= double(uh.size());
        const double tol = kWallDepartureVoxels * voxel_mm;
        // Only a converging wall no steeper than 45 deg is an axial wall a foot can stand out from:
        // a wall leaning out or stepped (an undercut) is read over the whole band, as it stands.
        if (!(slope < 0 && slope > -1)) first = 0;
        while (first > 0 && ds[first - 1] - (dm + slope * (hs[first - 1] - hm)) <= tol) --first;
      }
      hs.erase(hs.begin(), hs.begin() + long(first));
      ds.erase(ds.begin(), ds.begin() + long(first));
      plane.points[side] = int(hs.size());
      plane.foot_skipped[side] = int(first);
      // A wall converging toward occlusal comes nearer the axis as it rises: its slope is negative.
      plane.wall_deg[side] = -std::atan(fitSlope(hs, ds)) * kRadToDeg;
    }
    plane.toc_deg = plane.wall_deg[0] + plane.wall_deg[1];
  }

  // 6. Height, and the widths at the margin's bin between the outer voxel faces: a voxel reaches
  // half its footprint along the direction beyond its centre.
  shape.height_mm = h_max + half - margin_height_mm;
  auto widthAt = [&](size_t k) -> Result<double> {
    if (band_lo >= bins || prof[k].lo[band_lo] > prof[k].hi[band_lo])
      return Error{std::string("crown preparation: ") + shape.planes[k].name + " plane: no tooth at the margin"};
    const Vec3& d = dirs[k];
    const double footprint = voxel_mm * (std::abs(d.x) + std::abs(d.y) + std::abs(d.z));
    return prof[k].hi[band_lo] - prof[k].lo[band_lo] + footprint;
  };
  const Result<double> md = widthAt(0), bl = widthAt(1);
  if (!md) return md.error();
  if (!bl) return bl.error();
  shape.width_md_mm = *md, shape.width_bl_mm = *bl;
  shape.height_width_ratio = shape.height_mm / std::max(shape.width_md_mm, shape.width_bl_mm);
  return shape;
}

}  // namespace dentsim
