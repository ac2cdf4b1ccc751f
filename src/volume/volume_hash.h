// volumeHash: a tooth's identity, the same for the same voxels and frame however they are stored.
//
// Sessions name the tooth they were recorded on by this hash, and replay checks it before it
// drills; two runs of a session end on the same hash when they end on the same voxels. The storage
// layout (which bricks are tiles, where the pool put them) does not enter it: a dense brick whose
// voxels are all equal hashes as the tile it would compact to.
#pragma once

#include <cstdint>
#include <string>

#include "core/volume_frame.h"
#include "volume/brick_volume.h"

namespace dentsim {

// XXH3 (64 bits) over the level, voxel size and origin, then every brick in z, y, x order.
uint64_t volumeHash(const BrickVolume& voxels, const VolumeFrame& frame);
// The hash as 16 lower-case hex digits (what session files and reports show).
std::string volumeHashHex(const BrickVolume& voxels, const VolumeFrame& frame);
std::string hashHex(uint64_t hash);

}  // namespace dentsim
