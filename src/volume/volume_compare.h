// Per-tissue agreement of two brick volumes on the same grid (intersection over union), for round trips and scoring.
#pragma once

#include <cstdint>

#include "core/result.h"
#include "volume/brick_volume.h"

namespace dentsim {

// How far two volumes agree on one tissue. A voxel is "in" the tissue when it holds that material
// and is at least half full (2 * fill > 31), the threshold of the marching-cubes surface and of
// voxelSolid(). Counts are voxels; fill sums are in units of 1/31 voxel.
struct TissueOverlap {
  uint64_t a_voxels = 0;      // voxels in the tissue in a
  uint64_t b_voxels = 0;      // voxels in the tissue in b
  uint64_t intersection = 0;  // voxels in the tissue in both
  uint64_t union_voxels = 0;  // voxels in the tissue in either
  double iou = 1.0;           // intersection / union_voxels in [0,1]; 1 when both sets are empty
  // The soft version over fills, where a voxel of another material counts as fill 0:
  uint64_t min_fill_sum = 0;  // sum over voxels of min(fill_a, fill_b)
  uint64_t max_fill_sum = 0;  // sum over voxels of max(fill_a, fill_b)
  double soft_iou = 1.0;      // min_fill_sum / max_fill_sum in [0,1]; 1 when both hold none of the tissue
};

// Compares `tissue` (not Empty) in a and b voxel for voxel. The grids must be the same level; the
// caller makes sure they share a frame (voxel size and origin), which the bricks do not record.
// Bricks that hold none of the tissue in either volume cost one index read each.
// Errors: the levels differ.
Result<TissueOverlap> compareTissues(const BrickVolume& a, const BrickVolume& b, Material tissue);

}  // namespace dentsim
