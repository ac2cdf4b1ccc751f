// The built-in lower first molar: four nested, closed STL layers (enamel, dentin, pulp, caries) from implicit fields.
//
// Frame (mm, right-handed): x mesiodistal (mesial -x, distal +x), y buccolingual (buccal -y,
// lingual +y), z along the long axis with the crown up (+z). The cementoenamel junction (CEJ)
// lies at z = 0: the crown rises to the cusp tips at about z = 7.6, the roots reach down to the
// apices at about z = -13.5.
//
// Layer semantics (the voxelizer gives inner layers priority: pulp > caries > dentin > enamel):
//   enamel  the enamel shell: outer crown surface plus the dentino-enamel junction (DEJ), meeting
//           at the CEJ;
//   dentin  the dentin solid: DEJ plus root surfaces; it includes the pulp space;
//   pulp    chamber, horns and one canal per root, strictly inside the dentin;
//   caries  a lesion in the central fissure from the outer surface through the enamel into the
//           dentin, at least 1 mm from the pulp.
// Enamel and dentin are cut from one shared lattice, so their DEJ vertices are bit-identical
// (opposite orientation) and voxelizing the two leaves neither gap nor overlap there.
//
// Entry points:
//   generateMolar()      the four layers as welded, closed, outward meshes
//   kMolarLayers         the layers by tissue name, in the tissue table's order
//   molarToothField() .. the implicit fields behind them (negative inside), for tests and tools
#pragma once

#include <string_view>

#include "core/triangle_mesh.h"

namespace dentsim {

struct MolarLayers {
  TriangleMesh enamel;  // enamel shell [mm]
  TriangleMesh dentin;  // dentin solid, pulp space included [mm]
  TriangleMesh pulp;    // pulp chamber, horns and canals [mm]
  TriangleMesh caries;  // carious lesion [mm]

  // The layer of the tissue named `tissue` (the tissue table's name), or nullptr: the molar's own
  // layers (kMolarLayers), so that a tissue the molar lacks (cementum) simply has no layer.
  const TriangleMesh* layer(std::string_view tissue) const;
};

// The molar's layers, one row each, in the tissue table's order. The names are the table's, written
// here because `model` sits below `volume` and may not include the table; tests/model checks that
// every tissue of the table is a row, so a tissue added there fails the tests until the molar grows
// its layer (or that test says why the molar lacks it).
struct MolarLayerRow {
  const char* tissue;               // the tissue table's name
  TriangleMesh MolarLayers::*mesh;  // the layer in MolarLayers
  const char* description;          // what the layer holds, for the asset's STL header
};
inline constexpr MolarLayerRow kMolarLayers[] = {
    {"enamel", &MolarLayers::enamel, "enamel shell"},
    {"dentin", &MolarLayers::dentin, "dentin incl. pulp space"},
    {"pulp", &MolarLayers::pulp, "pulp"},
    {"caries", &MolarLayers::caries, "caries"},
};

inline const TriangleMesh* MolarLayers::layer(std::string_view tissue) const {
  for (const MolarLayerRow& row : kMolarLayers)
    if (tissue == row.tissue) return &(this->*row.mesh);
  return nullptr;
}

struct MolarOptions {
  // Lattice spacing [mm]. The default is what assets/teeth/ holds (about 134k triangles in all);
  // coarser values (0.2 .. 0.4) suit quick checks.
  double grid_mm = 0.27;
};

// Samples the fields on one lattice and extracts each layer by marching tetrahedra. Deterministic:
// the same options give bit-identical meshes on every run and build (no threads, no randomness,
// only + - * / and sqrt on doubles).
MolarLayers generateMolar(const MolarOptions& options = {});

// The fields, each negative inside its solid and roughly a distance [mm] near its surface.
double molarToothField(const Vec3d& p);   // the whole tooth's outer surface
double molarDentinField(const Vec3d& p);  // the dentin core: the DEJ in the crown, far negative in the roots
double molarPulpField(const Vec3d& p);    // the pulp space
double molarCariesField(const Vec3d& p);  // the lesion before it is clipped to the tooth

// The box that holds the tooth, with a margin [mm].
Bounds3 molarBounds();

}  // namespace dentsim
