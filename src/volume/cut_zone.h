// The cut zone: the target voxels a cut should remove (an ideal's cavity, or the caries with its access), and the leeway within reach of them.
//
// Scoring measures a cut against it, and the scripted careful dentist plans within it;
// docs/SCORING.md, "The allowed zone", gives the rules. Every tissue voxel falls in one of three
// zones: the target; the leeway, within leeway_mm (Euclidean, between voxel centres, the bound
// included) of a target voxel; and the container, the rest of the tooth. The target and the
// leeway together are the allowed zone.
//
// Contents
//   1. TargetMasks: the target voxels, one 512-bit mask per brick that holds any
//   2. The caries' access: the caries and every voxel on the line from it along the insertion axis
//   3. LeewayField: whether a voxel lies within the leeway of the target, brick by brick
//   4. ZoneGrid: the allowed zone as a dense mask over a box, for planning a cut
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A brick's linear index in a grid of brick_dim bricks per side.
inline uint64_t linearBrick(BrickCoord c, uint32_t brick_dim) {
  return c.x + uint64_t{brick_dim} * (c.y + uint64_t{brick_dim} * c.z);
}

// ---- 1. target masks -----------------------------------------------------------------------------

class TargetMasks {
 public:
  using Mask = std::array<uint64_t, DS_BRICK_VOXELS / 64>;  // bit n: voxel n of the brick (x fastest)

  explicit TargetMasks(uint32_t brick_dim) : brick_dim_(brick_dim) {}

  void set(BrickCoord b, uint32_t offset) {
    masks_[linearBrick(b, brick_dim_)][offset >> 6] |= uint64_t{1} << (offset & 63u);
  }
  // The brick's mask, or null when it holds no target voxel.
  const Mask* find(BrickCoord b) const {
    auto it = masks_.find(linearBrick(b, brick_dim_));
    return it == masks_.end() ? nullptr : &it->second;
  }
  static bool test(const Mask& m, uint32_t offset) { return (m[offset >> 6] >> (offset & 63u)) & 1u; }
  uint32_t brickDim() const { return brick_dim_; }
  bool empty() const { return masks_.empty(); }
  // The bricks that hold target voxels, by linear index.
  std::vector<uint64_t> bricks() const;

 private:
  uint32_t brick_dim_;
  std::unordered_map<uint64_t, Mask> masks_;
};

// ---- 2. the caries' access -------------------------------------------------------------------------

// Marks every caries voxel (fill > 0) of `initial`, and every voxel on the line from a caries voxel
// along +axis (unit, grid axes: the way the bur comes in), as target: the access a bur held along
// the insertion axis needs, with the tissue that the lesion undermines. Only bricks within
// `brick_reach` bricks of the tissue's bricks are marked; beyond them no tissue can be near. A
// neighbour voxel (an adjacent tooth) on a line is not marked: the access is the treated tooth's.
void markCariesAccess(const BrickVolume& initial, const Vec3& axis, uint32_t brick_reach, TargetMasks* masks);

// ---- 3. the leeway --------------------------------------------------------------------------------

// Answers, brick by brick, which voxels lie within `leeway_voxels` of a target voxel. A brick
// farther than that from every target brick has none (inBand() is false). For the others the
// squared distance is computed exactly, axis by axis, on a dense copy of the target around the brick.
class LeewayField {
 public:
  LeewayField(const TargetMasks& masks, double leeway_voxels);
  LeewayField(const LeewayField&) = delete;
  LeewayField& operator=(const LeewayField&) = delete;

  // Some voxel of brick b may lie within the leeway.
  bool inBand(BrickCoord b) const { return band_.count(linearBrick(b, masks_.brickDim())) != 0; }
  // Per voxel of brick b (x fastest): 1 within the leeway of a target voxel (a target voxel itself
  // included), else 0. Computed on the first call for a brick; the reference stays valid until a
  // call for another brick.
  const std::array<uint8_t, DS_BRICK_VOXELS>& near(BrickCoord b);

 private:
  void load(BrickCoord b);

  const TargetMasks& masks_;
  double limit2_ = 0.0;                         // the leeway squared, with a rounding allowance [voxels^2]
  int32_t reach_ = 0;                           // floor(leeway) [voxels]
  int32_t brick_reach_ = 1;                     // bricks on each side that the search may reach
  int64_t side_ = 0;                            // the dense block's side [voxels]
  std::unordered_set<uint64_t> band_;           // bricks within brick_reach_ of a target brick
  std::vector<uint8_t> bits_;                   // (side^3) target bits around the loaded brick, x fastest
  std::array<int64_t, 3> origin_{};             // the block's first voxel
  uint64_t loaded_ = ~uint64_t{0};              // linear index of the brick in near_
  std::array<uint8_t, DS_BRICK_VOXELS> near_{};
  std::vector<int64_t> fx_, fy_;                // scratch of the distance passes
};

// ---- 4. the allowed zone as a grid -------------------------------------------------------------------

// Whether each voxel of a box lies where a cut may go: the target, the leeway, or space that held no
// tissue at the start. A voxel outside the box is not known to be allowed: false. A neighbour voxel
// (an adjacent tooth) is never allowed, even within the leeway.
class ZoneGrid {
 public:
  // The box [lo, hi) in voxels, clipped to the grid.
  ZoneGrid(const BrickVolume& initial, const TargetMasks& masks, LeewayField& leeway, std::array<int64_t, 3> lo,
           std::array<int64_t, 3> hi);
  bool allowed(int64_t x, int64_t y, int64_t z) const {
    if (x < lo_[0] || y < lo_[1] || z < lo_[2] || x >= hi_[0] || y >= hi_[1] || z >= hi_[2]) return false;
    return cells_[size_t((x - lo_[0]) + size_[0] * ((y - lo_[1]) + size_[1] * (z - lo_[2])))] != 0;
  }
  bool target(int64_t x, int64_t y, int64_t z) const {
    if (x < lo_[0] || y < lo_[1] || z < lo_[2] || x >= hi_[0] || y >= hi_[1] || z >= hi_[2]) return false;
    return cells_[size_t((x - lo_[0]) + size_[0] * ((y - lo_[1]) + size_[1] * (z - lo_[2])))] == kTarget;
  }

 private:
  static constexpr uint8_t kAllowed = 1, kTarget = 2;
  std::array<int64_t, 3> lo_{}, hi_{}, size_{};
  std::vector<uint8_t> cells_;  // 0 not allowed, kAllowed, kTarget; x fastest
};

}  // namespace dentsim
