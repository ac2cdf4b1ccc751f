// builtinMolarTooth and builtinMolarNeighboursTooth: the embedded molar (and its neighbours) through the CPU voxelizer.
#include "sim/builtin_tooth.h"

#include <array>
#include <vector>

#include "model/builtin_assets.h"
#include "volume/tissue_table.h"
#include "volume/tooth_builder.h"
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

Result<ToothVolume> builtinMolarNeighboursTooth(int level) {
  auto molar = loadBuiltinMolar();
  if (!molar) return molar.error();
  auto teeth = loadBuiltinNeighbours();
  if (!teeth) return teeth.error();
  const std::vector<MeshLayer> molar_layers = builtinMolarLayers(*molar);
  // The voxelizer knows the treated tooth's four tissues; a neighbour is voxelized as a one-tissue
  // solid (enamel standing in) on the same grid, then laid in as Material::Neighbour.
  std::vector<MeshLayer> neighbour_layers;
  for (const NeighbourRow& row : kNeighbourTeeth) neighbour_layers.push_back({Material::Enamel, &((*teeth).*row.mesh), row.name});

  Bounds3 bounds;
  for (const MeshLayer& l : molar_layers) bounds.add(l.mesh->bounds());
  for (const MeshLayer& l : neighbour_layers) bounds.add(l.mesh->bounds());
  auto frame = fitGridToLevel(bounds, level);
  if (!frame) return frame.error();
  const VoxelizeOptions options;
  auto voxelize = [&](const std::vector<MeshLayer>& layers) -> Result<BrickVolume> {
    auto setup = makeRaySetup(layers, *frame, options);
    if (!setup) return setup.error();
    return voxelizeCpu(*setup, options);
  };
  auto molar_voxels = voxelize(molar_layers);
  if (!molar_voxels) return molar_voxels.error();
  auto neighbour_voxels = voxelize(neighbour_layers);
  if (!neighbour_voxels) return neighbour_voxels.error();

  // The frame is the molar's: its axes are the convention's and its occlusal centre is measured on
  // the molar alone, before the neighbours widen the tissue's extent.
  ToothVolume tooth{*frame, std::move(molar_voxels).value()};
  setConventionalAxes(tooth);
  addNeighbours(tooth.voxels, *neighbour_voxels);
  tooth.voxels.compact();
  return tooth;
}

}  // namespace dentsim
