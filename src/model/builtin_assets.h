// The built-in molar, its neighbours and the tools: the checked-in files under assets/, embedded into the library at build time.
//
// Entry points:
//   loadBuiltinMolar()       the four molar layers parsed from the embedded STL files
//   loadBuiltinNeighbours()  the molar's two neighbours (model/neighbour_generator.h) likewise
//   loadBuiltinTool(name)    one tool ("round_bur_010", see toolCatalog()) parsed likewise
//   builtinAssetBytes(path)  raw embedded bytes by path under assets/ ("teeth/molar_enamel.stl",
//                            "presets/default.json")
//   generateAssets()         what `dentsim make-tooth` writes: every mesh asset file, freshly generated
//
// The embedded bytes are whatever assets/ held when the library was built; generateAssets()
// reproduces teeth/ and tools/ byte for byte (a test checks this). presets/ holds the SimParams
// presets, which src/sim writes and checks (tests/sim/sim_params_test.cpp). When assets/ is empty (bootstrapping),
// the loaders return an error that says to run `dentsim make-tooth --out assets`.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "core/triangle_mesh.h"
#include "model/molar_generator.h"
#include "model/neighbour_generator.h"

namespace dentsim {

Result<MolarLayers> loadBuiltinMolar();
Result<NeighbourTeeth> loadBuiltinNeighbours();
Result<TriangleMesh> loadBuiltinTool(std::string_view name);

// Empty when no such file was embedded.
std::span<const uint8_t> builtinAssetBytes(std::string_view relative_path);
// Paths of every embedded file, relative to assets/, sorted.
std::vector<std::string> builtinAssetPaths();

// One file under assets/.
struct AssetFile {
  std::string path;            // relative to assets/, '/'-separated
  std::vector<uint8_t> bytes;  // the file's contents
};

struct GeneratedAssets {
  MolarLayers molar;                // the layers as written
  NeighbourTeeth neighbours;        // the molar's neighbours as written (their own default lattice)
  std::vector<TriangleMesh> tools;  // in toolCatalog() order
  std::vector<AssetFile> files;     // teeth/molar_*.stl, teeth/neighbour_*.stl, tools/*.stl, tools/tools.json
};

// Runs the generators and encodes every asset file (binary STL, fixed headers). Deterministic.
GeneratedAssets generateAssets(const MolarOptions& options = {});

// The file of a molar layer under assets/: "teeth/molar_enamel.stl".
inline std::string molarLayerFile(const MolarLayerRow& row) { return "teeth/molar_" + std::string(row.tissue) + ".stl"; }
// The file of a neighbour under assets/: "teeth/neighbour_premolar.stl".
inline std::string neighbourFile(const NeighbourRow& row) { return "teeth/neighbour_" + std::string(row.name) + ".stl"; }

}  // namespace dentsim
