// The crown preparation's reduction: how much was cut off the original tooth's occlusal surface and each axial wall, against the examiner's target bands.
//
// Entry point:
//   measureReduction(original, prepared, voxel_mm, insertion_axis, mesial, margin_height_mm, bands)
// Also here, shared with the margin and undercut measures: the voxel key (reductionVoxelKey), the
// frame (crownFrame) and the dense byte box of the teeth (CrownVoxelBox).
//
// Each original surface voxel (a tooth voxel with a face neighbour that is not tooth: empty or a
// neighbouring tooth) is a sample. Its outward normal is the sum of the offsets of the non-tooth
// voxels among its 26 neighbours. The reduction there is measured along the inward normal, as an
// examiner reads a reduction gauge held square to the surface: 0 when the voxel is still in the
// prepared tooth, else the distance from the original voxel's outer face to the first prepared
// voxel's outer face on that ray [mm] (to 1/8 voxel). A ray that leaves the original tooth, or goes
// down to the margin height, without meeting the preparation crosses a part taken off whole (an
// occlusal-axial corner, the rim above the shoulder): it has no wall to measure and is counted as
// `unreached`, in no region. So is an occlusal sample whose ray meets the preparation on an axial
// wall (the prepared voxel's normal, worked out the same way, in a wall's region): a gauge from a
// cusp's outer slope at the rim points down and in across that corner and reads the wall, which an
// examiner's occlusal reading does not (an over-tapered wall would otherwise read as occlusal
// over-reduction). A cusp cut away whole above the margin still shows, as the occlusal samples above
// it reach far down to the table.
//
// Heights are along the insertion axis from the grid origin, voxel centres at (i + 0.5) * voxel_mm
// on each grid axis (as eval/crown_prep_taper.h): a voxel is above the margin when its centre's
// height is over margin_height_mm. Regions, for samples above the margin: occlusal when the normal lies strictly within 45 degrees of the insertion axis;
// an axial wall when it lies strictly within 45 degrees of that wall's direction (perpendicular to
// the axis): mesial, distal = -mesial, buccal = axis x mesial, lingual = -buccal. A normal at exactly
// 45 degrees (a box's edge or corner voxel) belongs to no region (a tolerance of 1e-6 in the cosine).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

// Target reduction bands [mm] for an all-ceramic crown: occlusal 1.5-2.0, axial 1.0-1.5
// (Shillingburg et al., Fundamentals of Fixed Prosthodontics, 4th ed., ch. on all-ceramic
// preparations; Goodacre, Campagni & Aquilino 2001, J Prosthet Dent 85:363, "Tooth preparations for
// complete crowns"). Metal-ceramic and gold crowns take other bands from the caller.
struct ReductionBands {
  double occlusal_lo = 1.5;  // [mm] less is under-reduced
  double occlusal_hi = 2.0;  // [mm] more is over-reduced
  double axial_lo = 1.0;     // [mm]
  double axial_hi = 1.5;     // [mm]
};

// One region's figures; all 0 when it has no sample.
struct ReductionStats {
  int samples = 0;           // original surface voxels in the region whose ray met the preparation
  double mean_mm = 0;        // mean reduction [mm]
  // The median reading (nearest rank, core/percentile.h) [mm]: what the score grades on the
  // occlusal surface. A gauge ray from a cusp's outer slope at the rim points down and in, across the
  // corner the walls' laps took off whole, and may still reach the lowered table far in: up to 7.7
  // mm on the scripted professional's preparation, and a table left 1 mm high read within by its
  // mean. A wall's rays run across the axis to the wall itself, so its mean is its reading.
  double median_mm = 0;
  double min_mm = 0;         // [mm]
  double max_mm = 0;         // [mm]
  double under_share = 0;    // share of samples below the band's lo [0..1]
  double over_share = 0;     // share of samples above the band's hi [0..1]
};

enum class AxialWall : int { Mesial = 0, Distal = 1, Buccal = 2, Lingual = 3 };

struct CrownPrepReduction {
  ReductionStats occlusal;
  std::array<ReductionStats, 4> axial;  // indexed by AxialWall: mesial, distal, buccal, lingual
  int unreached = 0;                    // samples above the margin whose ray missed the preparation
  // Original surface voxels of a region under or over its band, as reductionVoxelKey(): the score
  // picture paints them blue (under) and red (over). In z, y, x order.
  std::vector<uint64_t> under_voxels;
  std::vector<uint64_t> over_voxels;
  // The prepared side, for painting the prepared surface: for each region sample whose ray met the
  // preparation, the prepared voxel it met (the sample itself when still unprepared), listed by
  // that sample's band: under, within or over. Sorted (z, y, x order), each voxel once per list; a
  // voxel met by samples of different bands is in each of their lists.
  std::vector<uint64_t> prepared_under;
  std::vector<uint64_t> prepared_within;
  std::vector<uint64_t> prepared_over;

  const ReductionStats& wall(AxialWall w) const { return axial[size_t(w)]; }
};

// A voxel's key in the lists above: 21 bits per axis, x lowest.
constexpr uint64_t reductionVoxelKey(uint32_t x, uint32_t y, uint32_t z) {
  return uint64_t{x} | (uint64_t{y} << 21) | (uint64_t{z} << 42);
}

// ---- Shared by the crown measures (reduction, margin, undercut) -------------------------------

// The insertion axis and the directions across it, unit, grid axes: buccal = axis x mesial.
struct CrownFrame {
  Vec3 axis, mesial, buccal;
};
// Normalizes insertion_axis and keeps mesial's part across it. Errors, naming `where`: a zero or
// non-finite axis, a mesial direction zero or along the axis.
Result<CrownFrame> crownFrame(const Vec3& insertion_axis, const Vec3& mesial, const std::string& where);
// What every measure of an original and a prepared tooth checks first: the same grid, a voxel size > 0.
Status checkCrownTeeth(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm, const std::string& where);

// The teeth as one byte per voxel over the box of bricks holding tooth tissue (isToothTissue) in
// any volume marked, padded by one voxel and clipped to the grid: the measures read each voxel and
// its neighbours many times, and BrickVolume::voxel walks the tree each time. Built brick by brick,
// so a level-9 tooth costs its own bricks, not the grid's.
struct CrownVoxelBox {
  int32_t lo[3] = {0, 0, 0};   // first voxel on each grid axis [voxels]
  int32_t n[3] = {0, 0, 0};    // extent on each axis [voxels]; 0 when no tooth
  std::vector<uint8_t> bits;   // (n[0] x n[1] x n[2]) flags per voxel, x fastest; the caller names the bits

  bool empty() const { return bits.empty(); }
  bool inBox(int32_t x, int32_t y, int32_t z) const {
    return x >= lo[0] && y >= lo[1] && z >= lo[2] && x < lo[0] + n[0] && y < lo[1] + n[1] && z < lo[2] + n[2];
  }
  size_t index(int32_t x, int32_t y, int32_t z) const {
    return (size_t(z - lo[2]) * size_t(n[1]) + size_t(y - lo[1])) * size_t(n[0]) + size_t(x - lo[0]);
  }
  // The flags at (x,y,z); 0 outside the box.
  uint8_t at(int32_t x, int32_t y, int32_t z) const { return inBox(x, y, z) ? bits[index(x, y, z)] : 0; }
  // The flags all six face neighbours of (x,y,z) share (a bit is clear when any neighbour lacks it):
  // a voxel with flag f is on that flag's surface when its neighbours' AND lacks f.
  uint8_t faceNeighboursAnd(int32_t x, int32_t y, int32_t z) const {
    if (x > lo[0] && y > lo[1] && z > lo[2] && x + 1 < lo[0] + n[0] && y + 1 < lo[1] + n[1] && z + 1 < lo[2] + n[2]) {
      const size_t i = index(x, y, z), sy = size_t(n[0]), sz = size_t(n[0]) * size_t(n[1]);
      return uint8_t(bits[i - 1] & bits[i + 1] & bits[i - sy] & bits[i + sy] & bits[i - sz] & bits[i + sz]);
    }
    return uint8_t(at(x - 1, y, z) & at(x + 1, y, z) & at(x, y - 1, z) & at(x, y + 1, z) & at(x, y, z - 1) & at(x, y, z + 1));
  }
};
// The box around the tooth tissue of a and of b (null: a alone; same grid as a), all flags 0.
CrownVoxelBox crownVoxelBox(const BrickVolume& a, const BrickVolume* b = nullptr);
// Sets tooth_bit on each of v's tooth voxels in the box, and enamel_bit (when not 0) on its enamel.
void markTooth(CrownVoxelBox& box, const BrickVolume& v, uint8_t tooth_bit, uint8_t enamel_bit = 0);

// original and prepared: the same grid (level); voxel_mm the voxel edge [mm], > 0; insertion_axis
// and mesial in grid axes (normalized here; mesial's part along the axis is dropped, so it must not
// be parallel to it); margin_height_mm the margin's height along the axis from the grid origin [mm]
// (samples with centres at or below it are the root, not measured). Errors: different grids, no tooth in either volume, bad axis or mesial,
// nothing of the original's surface above the margin.
Result<CrownPrepReduction> measureReduction(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                                            const Vec3& insertion_axis, const Vec3& mesial, double margin_height_mm,
                                            const ReductionBands& bands = {});

}  // namespace dentsim
