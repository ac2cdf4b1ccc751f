// The crown preparation's undercuts: columns cast down the insertion axis, those that leave the tooth and enter it again above the margin, their area by wall.
//
// The rule (docs/CROWN_PREPARATION.md says the same for examiners):
//
// Columns. A square lattice across the axis, one voxel apart, along mesial and buccal = axis x
// mesial, through voxel centres: for an axis along a grid axis, the grid's own columns. Each column
// is sampled from above the tooth down the axis every half voxel, reading the voxel that holds the
// sample; only tooth tissues count (isToothTissue), so a neighbour hanging over the tooth casts no
// shadow.
//
// Shadow. Walking down, the first tooth met is the surface a crown seats on. The column is
// shadowed when it then leaves the tooth at a voxel whose centre is above the margin height, and
// after a gap of at least one voxel (two samples) enters it again at a voxel whose centre is above
// the margin height less one voxel (so a shoulder's floor, whose top face is the margin, counts).
// A column off the grid's axes drifts across the grid's columns and would cross the pockets, less
// than a voxel deep, that a voxel staircase leaves along any sloping wall: its gap counts only where,
// at some sample, the tooth is also absent one voxel back against the drift (across the nearest
// grid axis). A real undercut is deeper than that; a column along a grid axis needs no such test. Every such re-entry's voxel is hidden
// surface.
//
// Flakes. The tooth above a gap must be at least kMinUndercutMm thick along the column: a run
// thinner than that is a grain the cutter left at half fill over the voxel it cut away under it (a
// level-9 preparation's finished walls carry 100-200 of them, one voxel thick, 0.056 mm, over an
// empty voxel), enamel with nothing under it that a seating crown crushes; a step of the wall is
// tooth all the way up.
//
// Patches. A crown seats over an overhang narrower than its cement space: a shadow counts only
// where it is at least kMinUndercutMm across, that is, where a square of k x k shadowed columns
// holds the column (a morphological opening of the shadow), k = ceil(kMinUndercutMm / voxel_mm) + 1:
// a step of the wall one voxel deep, on a wall that runs obliquely across the lattice, shadows two
// columns side by side, so the square is one column wider than the overhang it stands for. A shadow one column wide is a grain the cutter left at half fill hanging over the voxel
// it cut under it, or a step of a voxelized slope: a level-8 preparation by dentsim's scripted
// professional shows 30 to 40 of them scattered over its walls and table, 0.4-0.5 mm^2 together,
// and a level-9 one some 1,700 columns along the ridges its laps leave, 5.4 mm^2, none 0.1 mm deep.
// Each shadowed column left counts once, voxel_mm^2, on the wall its lattice point faces from
// the axis line through the centroid of the tooth above the margin: mesial within 45 degrees of
// mesial, distal, buccal and lingual likewise (exactly 45 goes to mesial or distal).
#include "eval/crown_prep_undercut.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "eval/crown_prep_reduction.h"

namespace dentsim {
namespace {

constexpr uint8_t kTooth = 1;
constexpr double kStep = 0.5;  // samples along a column [voxels]
constexpr int kMinGapSamples = 2;
// The narrowest overhang that counts [mm]: CAD/CAM crowns are milled with 0.05-0.1 mm of cement
// space inside, and a die spacer of 25-40 um fills smaller steps on a cast crown's die.
constexpr double kMinUndercutMm = 0.1;

}  // namespace

Result<UndercutMap> measureUndercut(const BrickVolume& prepared, double voxel_mm, const Vec3& insertion_axis,
                                    const Vec3& mesial, double margin_height_mm) {
  const std::string where = "crown undercut";
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm)) return makeError(where, "the voxel size must be > 0 mm");
  if (!std::isfinite(margin_height_mm)) return makeError(where, "the margin height is not finite");
  const Result<CrownFrame> frame = crownFrame(insertion_axis, mesial, where);
  if (!frame) return frame.error();
  const Vec3 a = frame->axis, m = frame->mesial, b = frame->buccal;

  CrownVoxelBox box = crownVoxelBox(prepared);
  markTooth(box, prepared, kTooth);
  const double margin = margin_height_mm / voxel_mm;  // [voxels]
  Vec3 centroid;
  double above = 0;
  bool any = false;
  for (int32_t z = box.lo[2]; z < box.lo[2] + box.n[2]; ++z)
    for (int32_t y = box.lo[1]; y < box.lo[1] + box.n[1]; ++y)
      for (int32_t x = box.lo[0]; x < box.lo[0] + box.n[0]; ++x) {
        if (!(box.bits[box.index(x, y, z)] & kTooth)) continue;
        any = true;
        const Vec3 p(x + 0.5, y + 0.5, z + 0.5);
        if (dot(p, a) > margin) centroid += p, above += 1;
      }
  if (!any) return makeError(where, "the prepared tooth holds no tooth");
  UndercutMap out;
  if (above == 0) return out;  // nothing above the margin: nothing to hide
  centroid = centroid / above;

  // The lattice's origin is a voxel centre; the box's corners bound the columns and their heights.
  const Vec3 origin(0.5, 0.5, 0.5);
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo, t_hi = -u_lo;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner(box.lo[0] + ((c & 1) ? box.n[0] : 0), box.lo[1] + ((c & 2) ? box.n[1] : 0),
                      box.lo[2] + ((c & 4) ? box.n[2] : 0));
    const Vec3 d = corner - origin;
    u_lo = std::min(u_lo, dot(d, m)), u_hi = std::max(u_hi, dot(d, m));
    v_lo = std::min(v_lo, dot(d, b)), v_hi = std::max(v_hi, dot(d, b));
    t_hi = std::max(t_hi, dot(d, a));
  }
  const double base = dot(origin, a);
  const double t_top = std::ceil(t_hi / kStep) * kStep;
  const double t_end = margin - 2.0 - base;  // below every voxel whose centre could count
  const double uc = dot(centroid - origin, m), vc = dot(centroid - origin, b);
  const double column_mm2 = voxel_mm * voxel_mm;
  // A column off the grid's axes drifts across the grid's columns as it goes down: `back` is one
  // voxel against that drift, across the nearest grid axis (zero for a column along a grid axis).
  int g = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(a[k]) > std::abs(a[g])) g = k;
  Vec3 back = a;
  back[g] = 0;
  back = norm(back) < 1e-9 ? Vec3{} : normalized(back);
  const bool drifts = norm(back) > 0;
  const int32_t i0 = int32_t(std::floor(u_lo)), i1 = int32_t(std::ceil(u_hi));
  const int32_t j0 = int32_t(std::floor(v_lo)), j1 = int32_t(std::ceil(v_hi));
  const auto ni = size_t(i1 - i0 + 1), nj = size_t(j1 - j0 + 1);
  // Samples of tooth, one after the other, that make an overhang at least kMinUndercutMm thick.
  const auto min_run = int(std::ceil(kMinUndercutMm / voxel_mm / kStep - 1e-9));
  std::vector<uint8_t> shadow(ni * nj, 0);                 // per lattice column
  std::vector<std::pair<size_t, uint64_t>> hidden;         // (column, voxel key)
  for (int32_t j = j0; j <= j1; ++j)
    for (int32_t i = i0; i <= i1; ++i) {
      const size_t column = size_t(i - i0) + ni * size_t(j - j0);
      const Vec3 foot = origin + double(i) * m + double(j) * b;
      bool seen = false, inside = false, gap_above = false, gap_deep = false, thick_above = false, shadowed = false;
      int gap = 0, run = 0;
      for (double t = t_top; t >= t_end; t -= kStep) {
        const Vec3 p = foot + t * a;
        const int32_t x = int32_t(std::floor(p.x)), y = int32_t(std::floor(p.y)), z = int32_t(std::floor(p.z));
        const double centre = dot(Vec3(x + 0.5, y + 0.5, z + 0.5), a);
        if (box.at(x, y, z) & kTooth) {
          if (seen && !inside && gap_above && gap_deep && thick_above && gap >= kMinGapSamples && centre > margin - 1.0) {
            shadowed = true;
            hidden.emplace_back(column, reductionVoxelKey(uint32_t(x), uint32_t(y), uint32_t(z)));
          }
          run = inside ? run + 1 : 1;
          seen = inside = true;
          gap = 0;
        } else {
          if (inside) {  // where the column leaves the tooth
            gap_above = centre > margin, gap_deep = !drifts;
            thick_above = run >= min_run;
          }
          inside = false;
          ++gap;
          if (!gap_deep) {
            const Vec3 q = p + back;
            gap_deep = !(box.at(int32_t(std::floor(q.x)), int32_t(std::floor(q.y)), int32_t(std::floor(q.z))) & kTooth);
          }
        }
      }
      shadow[column] = shadowed ? 1 : 0;
    }
  // The opening: a column is kept when some k x k square of shadowed columns holds it. Both halves
  // count squares with 2D prefix sums, so the cost does not grow with k: the erosion marks each
  // square's corner when the square is all shadow, the dilation keeps a column when some marked
  // corner lies within the k x k columns before it.
  const auto k = size_t(std::ceil(kMinUndercutMm / voxel_mm - 1e-9)) + 1;
  auto prefixSums = [&](const std::vector<uint8_t>& mask) {
    std::vector<uint32_t> sum((ni + 1) * (nj + 1), 0);
    for (size_t cb = 0; cb < nj; ++cb)
      for (size_t ca = 0; ca < ni; ++ca)
        sum[(ca + 1) + (ni + 1) * (cb + 1)] = uint32_t(mask[ca + ni * cb] ? 1 : 0) + sum[ca + (ni + 1) * (cb + 1)] +
                                              sum[(ca + 1) + (ni + 1) * cb] - sum[ca + (ni + 1) * cb];
    return sum;
  };
  // The count in columns [a0, a1) x [b0, b1).
  auto boxCount = [&](const std::vector<uint32_t>& sum, size_t a0, size_t b0, size_t a1, size_t b1) {
    return sum[a1 + (ni + 1) * b1] - sum[a0 + (ni + 1) * b1] - sum[a1 + (ni + 1) * b0] + sum[a0 + (ni + 1) * b0];
  };
  std::vector<uint8_t> corner(ni * nj, 0), kept(ni * nj, 0);
  if (ni >= k && nj >= k) {
    const std::vector<uint32_t> shadow_sum = prefixSums(shadow);
    for (size_t cb = 0; cb + k <= nj; ++cb)
      for (size_t ca = 0; ca + k <= ni; ++ca)
        corner[ca + ni * cb] = boxCount(shadow_sum, ca, cb, ca + k, cb + k) == k * k ? 1 : 0;
    const std::vector<uint32_t> corner_sum = prefixSums(corner);
    for (size_t cb = 0; cb < nj; ++cb)
      for (size_t ca = 0; ca < ni; ++ca)
        kept[ca + ni * cb] = boxCount(corner_sum, ca + 1 >= k ? ca + 1 - k : 0, cb + 1 >= k ? cb + 1 - k : 0, ca + 1, cb + 1) > 0;
  }
  for (int32_t j = j0; j <= j1; ++j)
    for (int32_t i = i0; i <= i1; ++i) {
      const size_t column = size_t(i - i0) + ni * size_t(j - j0);
      if (!kept[column]) continue;
      out.area_mm2 += column_mm2;
      const double du = double(i) - uc, dv = double(j) - vc;
      const AxialWall wall = std::abs(dv) <= std::abs(du) ? (du >= 0 ? AxialWall::Mesial : AxialWall::Distal)
                                                          : (dv > 0 ? AxialWall::Buccal : AxialWall::Lingual);
      out.wall_area_mm2[size_t(wall)] += column_mm2;
    }
  for (const auto& [column, key] : hidden)
    if (kept[column]) out.voxels.push_back(key);
  std::sort(out.voxels.begin(), out.voxels.end());
  out.voxels.erase(std::unique(out.voxels.begin(), out.voxels.end()), out.voxels.end());
  return out;
}

}  // namespace dentsim
