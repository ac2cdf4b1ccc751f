// Octree node counts: brick states bottom-up, then a top-down walk over nodes whose parents are mix.
#include "volume/octree_stats.h"

#include <algorithm>
#include <array>
#include <bit>
#include <optional>

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

// The states of one chunk's bricks and of the cubes above them up to the chunk: local[k] has side
// 2^k, local[0] being the chunk and the last level its bricks.
std::vector<std::vector<State>> chunkPyramid(const BrickVolume& volume, uint32_t cx, uint32_t cy, uint32_t cz,
                                             uint32_t span, size_t span_log) {
  std::vector<std::vector<State>> local(span_log + 1);
  local[span_log].resize(size_t(span) * span * span);
  for (uint32_t z = 0; z < span; ++z)
    for (uint32_t y = 0; y < span; ++y)
      for (uint32_t x = 0; x < span; ++x) {
        const BrickView b = volume.brick({cx * span + x, cy * span + y, cz * span + z});
        local[span_log][x + span * (y + span * z)] =
            b.uniform ? (voxelSolid(b.value) ? kBlack : kWhite) : pyramidOf(b.voxels).l3;
      }
  for (size_t k = span_log; k > 0; --k) {
    const size_t side = size_t{1} << (k - 1);
    local[k - 1].resize(side * side * side);
    reduceLevel(local[k].data(), uint32_t(side * 2), local[k - 1].data());
  }
  return local;
}

// Top-down over a pyramid of cubes (states[d] has side 2^d, states[0] one cube at level depth0 of
// `levels`): a node exists when its parent is mix. The root is counted unless its caller did;
// `leaf` counts what lies below a mix node of the last level.
template <class Leaf>
void countDown(const std::vector<std::vector<State>>& states, size_t depth0, bool count_root,
               std::vector<OctreeLevelCounts>& levels, Leaf&& leaf) {
  std::vector<uint8_t> exists{1}, next;
  for (size_t d = 0; d < states.size(); ++d) {
    const uint32_t side = 1u << d;
    const bool last = d + 1 == states.size();
    if (!last) next.assign(size_t(side) * 8 * side * side, 0);
    for (uint32_t z = 0; z < side; ++z)
      for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
          const size_t i = x + size_t(side) * (y + size_t(side) * z);
          if (!exists[i]) continue;
          const State s = states[d][i];
          if (d > 0 || count_root) count(levels[depth0 + d], s);
          if (s != kMix) continue;
          if (last) {
            leaf(x, y, z, depth0 + d);
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
}

}  // namespace

// Works chunk by chunk, so that memory and time follow the chunks and the bricks the surface
// crosses, not the grid: at level 13 the grid has 2^30 bricks, but a chunk that is a tile costs one
// read. Chunk states go bottom-up to the root; below a mix chunk, its bricks' states, then the
// voxels of its mix bricks.
OctreeCounts octreeNodeCounts(const BrickVolume& volume) {
  const int L = volume.level();
  const uint32_t bd = volume.brickDim();
  const uint32_t span = std::min<uint32_t>(bd, DS_CHUNK_DIM);  // a chunk's bricks per side inside the grid
  const uint32_t cd = bd / span;                                // chunks per side
  const size_t span_log = size_t(std::countr_zero(span));
  const size_t chunk_depth = size_t(L) - DS_BRICK_LOG2 - span_log;
  OctreeCounts result;
  result.levels.resize(size_t(L) + 1);

  std::vector<std::vector<State>> states(chunk_depth + 1);
  states[chunk_depth].resize(size_t(cd) * cd * cd);
  for (uint32_t z = 0; z < cd; ++z)
    for (uint32_t y = 0; y < cd; ++y)
      for (uint32_t x = 0; x < cd; ++x) {
        const std::optional<Voxel> tile = volume.chunkTile(x, y, z);
        states[chunk_depth][x + size_t(cd) * (y + size_t(cd) * z)] =
            tile ? (voxelSolid(*tile) ? kBlack : kWhite) : chunkPyramid(volume, x, y, z, span, span_log)[0][0];
      }
  for (size_t d = chunk_depth; d > 0; --d) {
    const size_t side = size_t{1} << (d - 1);
    states[d - 1].resize(side * side * side);
    reduceLevel(states[d].data(), uint32_t(side * 2), states[d - 1].data());
  }

  countDown(states, 0, true, result.levels, [&](uint32_t cx, uint32_t cy, uint32_t cz, size_t chunk_level) {
    countDown(chunkPyramid(volume, cx, cy, cz, span, span_log), chunk_level, false, result.levels,
              [&](uint32_t x, uint32_t y, uint32_t z, size_t brick_level) {
                const BrickView b = volume.brick({cx * span + x, cy * span + y, cz * span + z});
                countInsideBrick(pyramidOf(b.voxels), brick_level, result.levels);
              });
  });
  return result;
}

}  // namespace dentsim
