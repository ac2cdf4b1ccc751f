// builtinMolarTooth: the embedded molar layers through the CPU voxelizer.
#include "sim/builtin_tooth.h"

#include <vector>

#include "model/builtin_assets.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim {

Result<ToothVolume> builtinMolarTooth(int level) {
  auto molar = loadBuiltinMolar();
  if (!molar) return molar.error();
  const std::vector<MeshLayer> layers = {{Material::Enamel, &molar->enamel, "enamel"},
                                         {Material::Dentin, &molar->dentin, "dentin"},
                                         {Material::Pulp, &molar->pulp, "pulp"},
                                         {Material::Caries, &molar->caries, "caries"}};
  return voxelizeLayersCpu(layers, level);
}

}  // namespace dentsim
