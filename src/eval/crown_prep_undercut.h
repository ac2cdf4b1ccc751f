// The crown preparation's undercuts: prepared surface hidden from the path of insertion, cast along the insertion axis, in mm^2 and as voxels for a picture.
//
// A crown seats along the insertion axis. Any part of the preparation above the margin that a ray
// cast down the axis from above cannot reach without passing through the tooth is hidden from that
// path: the crown cannot seat over it. Implemented in eval/crown_prep_undercut.cpp, whose opening
// comment gives the rule (rays, what counts as above the margin, how the area is counted).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct UndercutMap {
  // The shadow: the area, in the plane across the axis, of the columns along the axis in which the
  // preparation above the margin hides some of its own surface [mm^2].
  double area_mm2 = 0;
  // The same split by the side it lies on, seen from the axis: mesial, distal, buccal, lingual (AxialWall's order) [mm^2].
  std::array<double, 4> wall_area_mm2{};
  // The hidden surface voxels of the prepared tooth, as reductionVoxelKey, for the picture.
  std::vector<uint64_t> voxels;
};

// prepared: the cut tooth; voxel_mm > 0; insertion_axis and mesial as eval/crown_prep_margin.h;
// margin_height_mm: heights along the axis from the grid origin at or below which nothing counts
// (the root under the finish line) [mm]. Errors: no tooth, a bad axis or mesial.
Result<UndercutMap> measureUndercut(const BrickVolume& prepared, double voxel_mm, const Vec3& insertion_axis,
                                    const Vec3& mesial, double margin_height_mm);

}  // namespace dentsim
