// The crown preparation's reduction: how much was cut off the original tooth's occlusal surface and each axial wall, against the examiner's target bands.
//
// Entry point:
//   measureReduction(original, prepared, voxel_mm, insertion_axis, mesial, margin_height_mm, bands)
//
// Each original surface voxel (a tooth voxel with a face neighbour that is not tooth: empty or a
// neighbouring tooth) is a sample. Its outward normal is the sum of the offsets of the non-tooth
// voxels among its 26 neighbours. The reduction there is measured along the inward normal, as an
// examiner reads a reduction gauge held square to the surface: 0 when the voxel is still in the
// prepared tooth, else the distance from the original voxel's outer face to the first prepared
// voxel's outer face on that ray [mm] (to 1/8 voxel). A ray that leaves the original tooth, or goes
// down to the margin height, without meeting the preparation crosses a part taken off whole (an
// occlusal-axial corner, the rim above the shoulder): it has no wall to measure and is counted as
// `unreached`, in no region. A cusp cut away whole above the margin still shows, as the occlusal
// samples above it reach far down.
//
// Regions, for samples whose height along the axis above the original's lowest voxel centre is over
// margin_height_mm: occlusal when the normal lies strictly within 45 degrees of the insertion axis;
// an axial wall when it lies strictly within 45 degrees of that wall's direction (perpendicular to
// the axis): mesial, distal = -mesial, buccal = axis x mesial, lingual = -buccal. A normal at exactly
// 45 degrees (a box's edge or corner voxel) belongs to no region (a tolerance of 1e-6 in the cosine).
#pragma once

#include <array>
#include <cstdint>
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

  const ReductionStats& wall(AxialWall w) const { return axial[size_t(w)]; }
};

// A voxel's key in the lists above: 21 bits per axis, x lowest.
constexpr uint64_t reductionVoxelKey(uint32_t x, uint32_t y, uint32_t z) {
  return uint64_t{x} | (uint64_t{y} << 21) | (uint64_t{z} << 42);
}

// original and prepared: the same grid (level); voxel_mm the voxel edge [mm], > 0; insertion_axis
// and mesial in grid axes (normalized here; mesial's part along the axis is dropped, so it must not
// be parallel to it); margin_height_mm the margin's height along the axis above the original tooth's
// lowest voxel centre [mm]. Errors: different grids, no tooth in either volume, bad axis or mesial,
// nothing of the original's surface above the margin.
Result<CrownPrepReduction> measureReduction(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                                            const Vec3& insertion_axis, const Vec3& mesial, double margin_height_mm,
                                            const ReductionBands& bands = {});

}  // namespace dentsim
