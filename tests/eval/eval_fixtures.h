// Tiny hand-built teeth for the eval tests: a 16^3 grid of 0.1 mm voxels, boxes of tissue set voxel by voxel.
#pragma once

#include <array>
#include <cstdint>

#include "eval/task.h"
#include "volume/brick_volume.h"

namespace dentsim::test {

constexpr double kVoxelMm = 0.1;
constexpr double kUnitMm3 = kVoxelMm * kVoxelMm * kVoxelMm / 31.0;  // one fill unit [mm^3]

// An empty grid of 2^level voxels per side at 0.1 mm, origin (0,0,0).
inline ToothVolume emptyTooth(int level = 4) {
  return ToothVolume{VolumeFrame::axisAligned(level, kVoxelMm, {0, 0, 0}), BrickVolume(level)};
}

// Sets every voxel of the box [lo, hi) to v.
inline void setBox(ToothVolume& t, std::array<uint32_t, 3> lo, std::array<uint32_t, 3> hi, Voxel v) {
  for (uint32_t z = lo[2]; z < hi[2]; ++z)
    for (uint32_t y = lo[1]; y < hi[1]; ++y)
      for (uint32_t x = lo[0]; x < hi[0]; ++x) t.voxels.setVoxel(x, y, z, v);
}

// A slab of full enamel, z in [0, 8), over the whole 16 x 16 base: 2048 voxels.
inline ToothVolume enamelSlab() {
  ToothVolume t = emptyTooth();
  setBox(t, {0, 0, 0}, {16, 16, 8}, makeVoxel(Material::Enamel));
  return t;
}

// A cavity task with the default coefficients.
inline Task cavityTask() {
  Task t;
  t.name = "test_cavity";
  t.kind = TaskKind::Cavity;
  t.target_s = 600;
  t.force_error_n = 3.0;
  return t;
}

inline Task cariesTask() {
  Task t;
  t.name = "test_caries";
  t.kind = TaskKind::Caries;
  t.target_s = 300;
  t.failure_s = 900;
  t.force_error_n = 3.0;
  return t;
}

}  // namespace dentsim::test
