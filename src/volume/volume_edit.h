// Geometric edits of a tooth's voxels (carving a ball), reporting the bricks they changed so meshes can follow.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/volume_frame.h"
#include "volume/brick_volume.h"

namespace dentsim {

// What one edit changed.
struct EditResult {
  std::vector<BrickCoord> dirty;  // bricks with at least one changed voxel, sorted (z, y, x), unique
  uint64_t voxels_changed = 0;    // voxels whose byte changed
  double removed_mm3 = 0.0;       // solid volume removed [mm^3]
};

// Removes a ball of `radius_mm` centred at `centre_mm` (simulation frame). A voxel keeps
// fill = min(fill, round(31 * (1 - c))), where c in [0,1] is the share of the voxel inside the ball,
// approximated by the signed distance of the voxel centre to the sphere over one voxel
// (c = clamp(0.5 - d / voxel, 0, 1), d > 0 outside). A voxel whose fill reaches 0 becomes empty.
// Voxels outside the grid are ignored.
// Cost: only bricks that reach the ball are read; a brick whose voxel centres all lie deeper than
// half a voxel inside becomes an empty tile without a copy, and each changed brick is written once. Preconditions (asserted): frame is
// the volume's frame (same level), radius_mm >= 0, a finite centre.
EditResult carveBall(BrickVolume& volume, const VolumeFrame& frame, const std::array<double, 3>& centre_mm,
                     double radius_mm);

}  // namespace dentsim
