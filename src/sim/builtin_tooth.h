// The built-in molar as a voxel tooth, alone or between its two neighbours, voxelized by the CPU reference: the same bytes on every machine, so sessions on it replay anywhere.
#pragma once

#include <vector>

#include "core/result.h"
#include "model/molar_generator.h"
#include "volume/brick_volume.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim {

// The molar's four layers as the voxelizer takes them (enamel, dentin, pulp, caries), each with its
// material and name. The views point into `molar`, which must outlive them.
std::vector<MeshLayer> builtinMolarLayers(const MolarLayers& molar);

// The four embedded layers (assets/teeth/molar_*.stl) in a 2^level grid fitted to them, voxelized
// on the CPU with the default options and compacted. Errors: a level out of range, missing assets.
Result<ToothVolume> builtinMolarTooth(int level);

// The molar between its neighbours (model/neighbour_generator.h: the second premolar mesially, the
// second molar distally), in a 2^level grid fitted to all three teeth: the molar's four layers as
// builtinMolarTooth voxelizes them, and each neighbour whole as Material::Neighbour in the voxels the
// molar leaves empty (the molar keeps a voxel the two share at a contact). The tooth's frame is the
// molar's: the convention's axes (setConventionalAxes) and the molar's own occlusal centre, so views
// and paths centre on the tooth being treated. Errors: as builtinMolarTooth.
Result<ToothVolume> builtinMolarNeighboursTooth(int level);

}  // namespace dentsim
