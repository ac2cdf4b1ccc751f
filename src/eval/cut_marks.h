// CutMarks: sparse amounts per voxel that the score picture paints, kept only for the bricks that hold any.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>

#include "volume/brick_volume.h"

namespace dentsim {

// Amounts per voxel [fill units, 0..31] that the score picture paints, kept only for bricks that
// hold any. Adding to a voxel again keeps the larger amount.
class CutMarks {
 public:
  void add(uint32_t x, uint32_t y, uint32_t z, uint32_t units);
  uint32_t at(uint32_t x, uint32_t y, uint32_t z) const;
  // Adds every mark of `other`, keeping the larger amount where both mark a voxel.
  void merge(const CutMarks& other);
  bool brickHasMarks(BrickCoord b) const { return bricks_.count(key(b)) != 0; }
  bool empty() const { return bricks_.empty(); }
  uint64_t voxelCount() const { return voxels_; }

 private:
  static uint64_t key(BrickCoord b) { return uint64_t{b.x} | (uint64_t{b.y} << 21) | (uint64_t{b.z} << 42); }
  std::unordered_map<uint64_t, std::array<uint8_t, DS_BRICK_VOXELS>> bricks_;
  uint64_t voxels_ = 0;
};

}  // namespace dentsim
