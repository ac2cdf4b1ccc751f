// builtinMolarTooth: the embedded molar layers through the CPU voxelizer.
#include "sim/builtin_tooth.h"

#include <vector>

#include "model/builtin_assets.h"
#include "volume/mesh_voxelizer.h"
#include "volume/tissue_table.h"

namespace dentsim {

Result<ToothVolume> builtinMolarTooth(int level) {
  auto molar = loadBuiltinMolar();
  if (!molar) return molar.error();
  // Every tissue the molar has a layer for, in table order (the voxelizer's priority is its own).
  std::vector<MeshLayer> layers;
  for (const TissueRow& row : kTissueTable)
    if (const TriangleMesh* mesh = molar->layer(row.name)) layers.push_back({row.material, mesh, row.name});
  return voxelizeLayersCpu(layers, level);
}

}  // namespace dentsim
