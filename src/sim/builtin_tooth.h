// The built-in molar as a voxel tooth, voxelized by the CPU reference: the same bytes on every machine, so sessions on it replay anywhere.
#pragma once

#include "core/result.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The four embedded layers (assets/teeth/molar_*.stl) in a 2^level grid fitted to them, voxelized
// on the CPU with the default options and compacted. Errors: a level out of range, missing assets.
Result<ToothVolume> builtinMolarTooth(int level);

}  // namespace dentsim
