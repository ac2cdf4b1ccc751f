// builtinMolarTooth: the embedded molar layers through the CPU voxelizer.
#include "sim/builtin_tooth.h"

#include <vector>

#include "model/builtin_assets.h"
#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"

namespace dentsim {

// Every tissue the molar has a layer for, in table order (the voxelizer's priority is its own).
std::vector<MeshLayer> builtinMolarLayers(const MolarLayers& molar) {
  std::vector<MeshLayer> layers;
  for (const TissueRow& row : kTissueTable)
    if (const TriangleMesh* mesh = molar.layer(row.name)) layers.push_back({row.material, mesh, row.name});
  return layers;
}

Result<ToothVolume> builtinMolarTooth(int level) {
  auto molar = loadBuiltinMolar();
  if (!molar) return molar.error();
  auto tooth = voxelizeLayersCpu(builtinMolarLayers(*molar), level);
  if (!tooth) return tooth;
  // The generator builds the molar in the convention's frame (assets/README.md): its axes are given, not found.
  setConventionalAxes(*tooth);
  return tooth;
}

}  // namespace dentsim
