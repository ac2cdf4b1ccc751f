// volumeHash: XXH3 over the frame and the bricks in canonical form.
#include "volume/volume_hash.h"

#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <memory>

namespace dentsim {

uint64_t volumeHash(const BrickVolume& voxels, const VolumeFrame& frame) {
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(), &XXH3_freeState);
  XXH3_64bits_reset(state.get());
  const int32_t level = voxels.level();
  XXH3_64bits_update(state.get(), &level, sizeof level);
  XXH3_64bits_update(state.get(), &frame.voxel_mm, sizeof frame.voxel_mm);
  XXH3_64bits_update(state.get(), frame.origin_mm.data(), sizeof frame.origin_mm);
  // Tiles are runs of one byte; a run is fed as (count, value) when it ends, so an empty grid
  // costs a few updates, not one per brick.
  uint64_t run = 0;
  Voxel run_value = 0;
  auto endRun = [&] {
    if (run == 0) return;
    const uint8_t tag = 0;
    XXH3_64bits_update(state.get(), &tag, 1);
    XXH3_64bits_update(state.get(), &run, sizeof run);
    XXH3_64bits_update(state.get(), &run_value, 1);
    run = 0;
  };
  voxels.forEachBrick([&](const BrickView& b) {
    Voxel value = b.value;
    bool uniform = b.uniform;
    if (!uniform) uniform = std::all_of(b.voxels, b.voxels + DS_BRICK_VOXELS, [&](Voxel v) { return v == b.voxels[0]; });
    if (uniform) {
      if (!b.uniform) value = b.voxels[0];
      if (run > 0 && value != run_value) endRun();
      run_value = value;
      ++run;
      return;
    }
    endRun();
    const uint8_t tag = 1;
    XXH3_64bits_update(state.get(), &tag, 1);
    XXH3_64bits_update(state.get(), b.voxels, DS_BRICK_VOXELS);
  });
  endRun();
  return XXH3_64bits_digest(state.get());
}

std::string hashHex(uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string volumeHashHex(const BrickVolume& voxels, const VolumeFrame& frame) {
  return hashHex(volumeHash(voxels, frame));
}

}  // namespace dentsim
