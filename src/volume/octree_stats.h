// The paper's octree node counts (black, white and mix nodes per level, its Table 2), computed from a brick volume.
#pragma once

#include <cstdint>
#include <vector>

#include "volume/brick_volume.h"

namespace dentsim {

// A voxel counts as solid (black) when it holds a tissue at least half full (fill >= 16 of 31),
// the same threshold as the marching-cubes surface; the paper's binary octree is the case
// fill in {0, 31}.
constexpr bool voxelSolid(Voxel v) {
  return voxelMaterial(v) != Material::Empty && voxelFill(v) * 2 > DS_FILL_FULL;
}

struct OctreeLevelCounts {
  uint64_t black = 0;  // nodes wholly solid
  uint64_t white = 0;  // nodes wholly empty
  uint64_t mix = 0;    // nodes with both; only these have children
};

// Counts of the binary octree that the volume's occupancy defines: level 0 is the root (the whole
// grid), level L the voxels. A node exists only if its parent is mix, as in a pointer octree.
struct OctreeCounts {
  std::vector<OctreeLevelCounts> levels;  // (L + 1) entries, root first
  uint64_t nodes() const {
    uint64_t n = 0;
    for (const auto& l : levels) n += l.black + l.white + l.mix;
    return n;
  }
};

OctreeCounts octreeNodeCounts(const BrickVolume& volume);

}  // namespace dentsim
