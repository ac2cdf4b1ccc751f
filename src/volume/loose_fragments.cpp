// Loose pieces of tooth: the solid tooth's pieces by flood over the tissue's brick box, all but the largest cleared.
#include "volume/loose_fragments.h"

#include <algorithm>
#include <array>
#include <deque>

#include "volume/half_fill.h"
#include "volume/voxel_grid_ops.h"

namespace dentsim {

LooseFragments dropLooseFragments(BrickVolume& volume) {
  LooseFragments out;
  const BrickBox bricks = tissueBricks(volume);
  if (bricks.empty()) return out;
  const std::array<uint32_t, 3> lo{bricks.lo.x * DS_BRICK_DIM, bricks.lo.y * DS_BRICK_DIM, bricks.lo.z * DS_BRICK_DIM};
  const std::array<int32_t, 3> d{int32_t((bricks.hi.x - bricks.lo.x + 1) * DS_BRICK_DIM),
                                 int32_t((bricks.hi.y - bricks.lo.y + 1) * DS_BRICK_DIM),
                                 int32_t((bricks.hi.z - bricks.lo.z + 1) * DS_BRICK_DIM)};
  const uint64_t n = uint64_t(d[0]) * uint64_t(d[1]) * uint64_t(d[2]);
  VoxelBits solid(n);
  volume.forEachBrick([&](const BrickView& b) {
    if (b.coord.x < bricks.lo.x || b.coord.y < bricks.lo.y || b.coord.z < bricks.lo.z || b.coord.x > bricks.hi.x ||
        b.coord.y > bricks.hi.y || b.coord.z > bricks.hi.z)
      return;
    if (b.uniform && !isSolidTooth(b.value)) return;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      if (!isSolidTooth(b.at(i))) continue;
      const std::array<int64_t, 3> c{int64_t(b.coord.x * DS_BRICK_DIM + (i & 7u) - lo[0]),
                                     int64_t(b.coord.y * DS_BRICK_DIM + ((i >> 3) & 7u) - lo[1]),
                                     int64_t(b.coord.z * DS_BRICK_DIM + (i >> 6) - lo[2])};
      solid.set(voxelIndex(c, d));
    }
  });
  std::deque<uint64_t> queue;
  VoxelBits seen(n);
  uint64_t best = 0, best_start = 0, total = 0, pieces = 0;
  for (uint64_t l = 0; l < n; ++l) {
    if (!solid.test(l) || seen.test(l)) continue;
    const VoxelPiece p = floodPiece(solid, seen, d, l, queue);
    ++pieces;
    total += p.voxels;
    if (p.voxels > best) {
      out.largest = std::max(out.largest, best);
      best = p.voxels;
      best_start = l;
    } else {
      out.largest = std::max(out.largest, p.voxels);
    }
  }
  if (pieces <= 1) return out;
  out.pieces = pieces - 1;
  out.voxels = total - best;
  VoxelBits tooth(n);
  floodPiece(solid, tooth, d, best_start, queue);
  const Voxel empty = makeVoxel(Material::Empty);
  for (uint64_t l = 0; l < n; ++l) {
    if (!solid.test(l) || tooth.test(l)) continue;
    const std::array<int64_t, 3> c = voxelCoords(l, d);
    volume.setVoxel(uint32_t(c[0]) + lo[0], uint32_t(c[1]) + lo[1], uint32_t(c[2]) + lo[2], empty);
  }
  return out;
}

}  // namespace dentsim
