// Volumes shared by the mesher tests (CPU and GPU): random bricks that reach every corner case.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "volume/brick_layout.h"
#include "volume/brick_volume.h"

namespace dentsim::test {

// What the noisy bricks of randomVolume hold. The GPU tests keep to the four tissues; the block
// mesher's tests also want the spare codes 0 and 5..7, which no importer writes but a byte can hold.
enum class NoiseMaterials {
  Tissues,   // 1..4: a tooth's own tissues (enamel, dentin, pulp, caries), no neighbour
  AnyCode,   // 0..7
};

// Random bricks, seeded: per brick one of six kinds, drawn evenly: empty; a tile of one tissue; three
// kinds of a random plane through the brick with a one-voxel fill ramp (so surfaces are not all
// noise); and noise of every fill. Every corner configuration, tissue pairing and the grid's borders
// turn up. The draws' order is part of the data: tests pin counts made on these volumes.
inline BrickVolume randomVolume(int level, uint32_t seed, NoiseMaterials noise) {
  BrickVolume vol(level);
  std::mt19937 rng(seed);
  const uint32_t bd = vol.brickDim();
  std::array<Voxel, DS_BRICK_VOXELS> buf{};
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) {
        const uint32_t kind = rng() % 6;
        if (kind == 0) continue;  // empty
        if (kind == 1) {
          vol.setBrickUniform({x, y, z}, makeVoxel(Material(1 + rng() % 4)));
          continue;
        }
        const double n[3] = {double(rng() % 200) - 100, double(rng() % 200) - 100, double(rng() % 200) - 100};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-9;
        const double off = double(rng() % 80) / 10.0 - 4.0;
        const bool noisy = kind == 5;
        for (uint32_t k = 0; k < 8; ++k)
          for (uint32_t j = 0; j < 8; ++j)
            for (uint32_t i = 0; i < 8; ++i) {
              const double d = ((i - 3.5) * n[0] + (j - 3.5) * n[1] + (k - 3.5) * n[2]) / len - off;
              int fill = int(std::lround(std::clamp(0.5 - d, 0.0, 1.0) * 31.0));
              if (noisy) fill = int(rng() % 32);
              const uint32_t material = noisy && noise == NoiseMaterials::AnyCode ? rng() % 8 : 1 + rng() % 4;
              buf[layout::brickCoordToOffset(i, j, k)] = fill ? Voxel(layout::makeVoxel(material, uint32_t(fill))) : Voxel(0);
            }
        vol.setBrick({x, y, z}, buf.data());
      }
  return vol;
}

}  // namespace dentsim::test
