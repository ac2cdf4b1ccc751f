// Octree node counts: brick states bottom-up, then a top-down walk over nodes whose parents are mix.
#include "volume/octree_stats.h"

#include <array>

namespace dentsim {
namespace {

enum State : uint8_t { kWhite = 0, kBlack = 1, kMix = 2 };

State combine(State acc, State child, bool first) {
  if (first) return child;
  return acc == child ? acc : kMix;
}

void count(OctreeLevelCounts& c, State s) {
  if (s == kWhite) ++c.white;
  else if (s == kBlack) ++c.black;
  else ++c.mix;
}

// States of one dense brick's sub-cubes: level 0 = the 8^3 voxels, 1 = 4^3 cubes of 2^3, 2 = 2^3
// cubes of 4^3, 3 = the brick. Index inside each level: x + n*(y + n*z) for side n.
struct BrickPyramid {
  std::array<State, 512> l0{};
  std::array<State, 64> l1{};
  std::array<State, 8> l2{};
  State l3 = kWhite;
};

// Each cube of the coarse level (side fine_side/2) takes the combined state of its 8 children.
// Index inside a level: x + side*(y + side*z). Serves the brick pyramid and the grid pyramid alike.
void reduceLevel(const State* fine, uint32_t fine_side, State* coarse) {
  const size_t side = fine_side / 2, fside = fine_side;
  for (size_t z = 0; z < side; ++z)
    for (size_t y = 0; y < side; ++y)
      for (size_t x = 0; x < side; ++x) {
        State s = kWhite;
        for (uint32_t c = 0; c < 8; ++c) {
          const size_t fx = 2 * x + (c & 1), fy = 2 * y + ((c >> 1) & 1), fz = 2 * z + (c >> 2);
          s = combine(s, fine[fx + fside * (fy + fside * fz)], c == 0);
        }
        coarse[x + side * (y + side * z)] = s;
      }
}

BrickPyramid pyramidOf(const Voxel* voxels) {
  BrickPyramid p;
  for (uint32_t z = 0; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x)
        p.l0[x + 8 * (y + 8 * z)] = voxelSolid(voxels[layout::brickCoordToOffset(x, y, z)]) ? kBlack : kWhite;
  reduceLevel(p.l0.data(), 8, p.l1.data());
  reduceLevel(p.l1.data(), 4, p.l2.data());
  reduceLevel(p.l2.data(), 2, &p.l3);
  return p;
}

// Adds the nodes below a mix brick at depth `depth` (the brick's own level) to `levels`.
void countInsideBrick(const BrickPyramid& p, size_t depth, std::vector<OctreeLevelCounts>& levels) {
  for (uint32_t c2 = 0; c2 < 8; ++c2) {
    const uint32_t x2 = c2 & 1, y2 = (c2 >> 1) & 1, z2 = c2 >> 2;
    const State s2 = p.l2[x2 + 2 * (y2 + 2 * z2)];
    count(levels[depth + 1], s2);
    if (s2 != kMix) continue;
    for (uint32_t c1 = 0; c1 < 8; ++c1) {
      const uint32_t x1 = 2 * x2 + (c1 & 1), y1 = 2 * y2 + ((c1 >> 1) & 1), z1 = 2 * z2 + (c1 >> 2);
      const State s1 = p.l1[x1 + 4 * (y1 + 4 * z1)];
      count(levels[depth + 2], s1);
      if (s1 != kMix) continue;
      for (uint32_t c0 = 0; c0 < 8; ++c0) {
        const uint32_t x0 = 2 * x1 + (c0 & 1), y0 = 2 * y1 + ((c0 >> 1) & 1), z0 = 2 * z1 + (c0 >> 2);
        count(levels[depth + 3], p.l0[x0 + 8 * (y0 + 8 * z0)]);
      }
    }
  }
}

}  // namespace

OctreeCounts octreeNodeCounts(const BrickVolume& volume) {
  const int L = volume.level();
  const size_t brick_depth = size_t(L) - DS_BRICK_LOG2;
  OctreeCounts result;
  result.levels.resize(size_t(L) + 1);

  // Bottom-up: the state of every brick, then of every coarser cube up to the root.
  std::vector<std::vector<State>> states(brick_depth + 1);
  const uint32_t bd = volume.brickDim();
  states[brick_depth].resize(size_t(bd) * bd * bd);
  volume.forEachBrick([&](const BrickView& b) {
    const size_t i = b.coord.x + size_t(bd) * (b.coord.y + size_t(bd) * b.coord.z);
    states[brick_depth][i] = b.uniform ? (voxelSolid(b.value) ? kBlack : kWhite) : pyramidOf(b.voxels).l3;
  });
  for (size_t d = brick_depth; d > 0; --d) {
    const size_t side = size_t{1} << (d - 1);
    states[d - 1].resize(side * side * side);
    reduceLevel(states[d].data(), uint32_t(side * 2), states[d - 1].data());
  }

  // Top-down: a node exists when its parent exists and is mix.
  std::vector<uint8_t> exists{1}, next;
  for (size_t d = 0; d <= brick_depth; ++d) {
    const uint32_t side = 1u << d;
    const bool last = d == brick_depth;
    if (!last) next.assign(size_t(side) * 8 * side * side, 0);
    for (uint32_t z = 0; z < side; ++z)
      for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
          const size_t i = x + size_t(side) * (y + size_t(side) * z);
          if (!exists[i]) continue;
          const State s = states[d][i];
          count(result.levels[d], s);
          if (s != kMix) continue;
          if (last) {
            countInsideBrick(pyramidOf(volume.brick({x, y, z}).voxels), d, result.levels);
            continue;
          }
          const uint32_t fine = side * 2;
          for (uint32_t c = 0; c < 8; ++c) {
            const uint32_t fx = 2 * x + (c & 1), fy = 2 * y + ((c >> 1) & 1), fz = 2 * z + (c >> 2);
            next[fx + size_t(fine) * (fy + size_t(fine) * fz)] = 1;
          }
        }
    exists.swap(next);
  }
  return result;
}

}  // namespace dentsim
