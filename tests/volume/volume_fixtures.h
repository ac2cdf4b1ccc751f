// Small helpers of the volume tests: boxes of tissue set voxel by voxel.
#pragma once

#include <array>
#include <cstdint>

#include "volume/brick_volume.h"

namespace dentsim::test {

// Sets every voxel of the box [lo, hi) to `value`.
inline void setBox(BrickVolume& v, std::array<uint32_t, 3> lo, std::array<uint32_t, 3> hi, Voxel value) {
  for (uint32_t z = lo[2]; z < hi[2]; ++z)
    for (uint32_t y = lo[1]; y < hi[1]; ++y)
      for (uint32_t x = lo[0]; x < hi[0]; ++x) v.setVoxel(x, y, z, value);
}

}  // namespace dentsim::test
