// Where a cut surface lies in a voxel: the half-full rule that every reading of a cut shape shares.
//
// The cutter wears a voxel down fill unit by fill unit and leaves it with its tissue and what fill
// is left. Marching cubes puts the surface at half fill, so a voxel at least half full (16 of 31)
// is inside it: the score picture's surface, the surface agreement's tissue and the crown
// preparation's measures all read the tooth at this level, never by the tissue code alone (which
// would count the worn grains a bur leaves on every cut wall as standing tooth).
#pragma once

#include <cstdint>

#include "volume/brick_volume.h"
#include "volume/tissue_table.h"

namespace dentsim {

inline constexpr uint32_t kHalfFill = 16;  // fill units of DS_FILL_FULL (31) at or above which a voxel is inside

constexpr bool isHalfFull(Voxel v) { return voxelFill(v) >= kHalfFill; }
// A tooth tissue (not empty, not a neighbour) at least half full.
constexpr bool isSolidTooth(Voxel v) { return isToothTissue(voxelMaterial(v)) && isHalfFull(v); }

}  // namespace dentsim
