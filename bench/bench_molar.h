// The built-in molar as the benchmarks measure it: the embedded layers, or freshly generated ones while assets/ is empty.
#pragma once

#include <string>
#include <vector>

#include "core/triangle_mesh.h"
#include "model/molar_generator.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::bench {

struct BenchMolar {
  MolarLayers molar;        // the four layers [mm]
  std::string description;  // where they came from, for the reports

  // Views of the four layers for the voxelizer (builtinMolarLayers); valid while this lives.
  std::vector<MeshLayer> layers() const;
  Bounds3 bounds() const;   // of all four layers [mm]
};

// The embedded molar; a bench still runs before `dentsim make-tooth` has filled assets/, on the
// same meshes generated in memory, and its description says so.
BenchMolar loadBenchMolar();

}  // namespace dentsim::bench
