// CutMarks: the per-brick arrays of marked amounts.
#include "eval/cut_marks.h"

#include <algorithm>

namespace dentsim {

void CutMarks::add(uint32_t x, uint32_t y, uint32_t z, uint32_t units) {
  if (units == 0) return;
  auto [it, inserted] = bricks_.try_emplace(key({x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, z >> DS_BRICK_LOG2}));
  if (inserted) it->second.fill(0);
  uint8_t& v = it->second[layout::brickCoordToOffset(x & 7u, y & 7u, z & 7u)];
  if (v == 0) ++voxels_;
  v = uint8_t(std::max<uint32_t>(v, std::min<uint32_t>(units, DS_FILL_FULL)));
}

void CutMarks::merge(const CutMarks& other) {
  for (const auto& [brick, marks] : other.bricks_) {
    auto [it, inserted] = bricks_.try_emplace(brick);
    if (inserted) it->second.fill(0);
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      if (marks[n] == 0) continue;
      if (it->second[n] == 0) ++voxels_;
      it->second[n] = std::max(it->second[n], marks[n]);
    }
  }
}

uint32_t CutMarks::at(uint32_t x, uint32_t y, uint32_t z) const {
  auto it = bricks_.find(key({x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, z >> DS_BRICK_LOG2}));
  return it == bricks_.end() ? 0u : it->second[layout::brickCoordToOffset(x & 7u, y & 7u, z & 7u)];
}

}  // namespace dentsim
