// builtinMolarTooth: the embedded molar layers through the CPU voxelizer.
#include "sim/builtin_tooth.h"

#include <vector>

#include "model/builtin_assets.h"

namespace dentsim {

std::vector<MeshLayer> builtinMolarLayers(const MolarLayers& molar) {
  return {{Material::Enamel, &molar.enamel, "enamel"},
          {Material::Dentin, &molar.dentin, "dentin"},
          {Material::Pulp, &molar.pulp, "pulp"},
          {Material::Caries, &molar.caries, "caries"}};
}

Result<ToothVolume> builtinMolarTooth(int level) {
  auto molar = loadBuiltinMolar();
  if (!molar) return molar.error();
  return voxelizeLayersCpu(builtinMolarLayers(*molar), level);
}

}  // namespace dentsim
