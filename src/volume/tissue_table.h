// The tissue table: every tissue dentsim knows, one row each; every list, name and colour of tissues derives from it.
//
// Contents
//   1. The row: name, material code, NIfTI label, colours, draw order, default touch and look
//   2. The table (add a tissue here; docs/TISSUES.md walks through one)
//   3. Look-ups and derived lists, checked at compile time
//
// The table lives in `volume` because the material code is the volume's fact and every stage above
// may read it. The default touch and look are plain numbers here, not sim's TissueParams or render's
// TissueLook: `volume` knows neither stage, and each stage copies the numbers into its own struct.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string>

#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. the row --------------------------------------------------------------------------------------

// How a tissue feels and cuts by default (sim's TissueParams; the fields are explained there).
struct TissueTouchDefaults {
  double stiffness_n_per_mm3;  // [N/mm^3], > 0
  double damping_s_per_mm;     // Hunt-Crossley damping [s/mm], >= 0
  double friction;             // Coulomb coefficient [-], in [0, 2]
  double hardness;             // ease of cutting, the paper's "hardness" [0..1]
};

// How a tissue looks on screen by default (render's TissueLook): Phong colours and opacity. Alpha < 1
// draws the tissue translucent, over the opaque ones.
struct TissueLookDefaults {
  double ambient[3];   // [0..1] r, g, b
  double diffuse[3];   // [0..1] r, g, b
  double specular[3];  // [0..1] r, g, b
  double alpha;        // opacity [0..1]
  double shininess;    // Phong exponent [1..512]
};

// Three colours, because they are three roles with different values, not one fact written thrice:
// the on-screen look is lit Phong material tuned against the translucent enamel; the score picture
// paints flat, light colours so that the red over-cut and blue under-cut fog read over them; the mesh
// file's 8-bit vertex colours follow stained atlas sections for viewers outside dentsim (pulp red,
// where the score picture keeps it pink so that it stays apart from the over-cut red).
struct TissueRow {
  const char* name;          // lower case: preset keys, score JSON keys, CLI names ("enamel")
  Material material;         // the voxel's material code (brick_layout.h DS_MAT_*)
  int32_t nifti_label;       // label value in exported NIfTI volumes (`dentsim export`)
  int draw_order;            // the renderer draws opaque tissues in rising order, translucent ones in falling
  double score_rgb[3];       // base colour in the score picture [0..1]
  uint8_t mesh_rgb[3];       // PLY vertex colour (`dentsim mesh`, `dentsim demo`) [0..255]
  TissueTouchDefaults touch; // default tactile values (SimParams::tissues)
  TissueLookDefaults look;   // default look (render's LookParams::looks)
};

// ---- 2. the table ------------------------------------------------------------------------------------

// Touch: stiffness, damping and friction are dentsim's tuning; hardness is the paper's default.
// Looks: after the tissues' appearance in extracted teeth; the enamel lets the layers beneath show.
// Rows are in material-code order, which is also the order presets, score JSON and the UI list them.
inline constexpr TissueRow kTissueTable[] = {
    {"enamel", Material::Enamel, 1, 0, {0.93, 0.90, 0.80}, {240, 238, 228},
     {2000.0, 0.0005, 0.15, 0.1},
     {{0.26, 0.26, 0.24}, {0.92, 0.90, 0.84}, {0.55, 0.55, 0.55}, 0.75, 48.0}},
    {"dentin", Material::Dentin, 2, 1, {0.88, 0.77, 0.48}, {222, 196, 128},
     {1200.0, 0.001, 0.25, 0.1},
     {{0.24, 0.21, 0.14}, {0.90, 0.80, 0.56}, {0.20, 0.20, 0.18}, 1.0, 12.0}},
    {"pulp", Material::Pulp, 3, 2, {0.90, 0.55, 0.60}, {200, 40, 50},
     {40.0, 0.01, 0.5, 1.0},
     {{0.22, 0.06, 0.06}, {0.82, 0.24, 0.22}, {0.30, 0.25, 0.25}, 1.0, 24.0}},
    {"caries", Material::Caries, 4, 3, {0.50, 0.32, 0.15}, {110, 70, 35},
     {300.0, 0.004, 0.4, 0.5},
     {{0.12, 0.08, 0.04}, {0.45, 0.30, 0.14}, {0.08, 0.08, 0.06}, 1.0, 6.0}},
    // An adjacent tooth, whole and of one tissue: it feels and cuts as enamel, its outer layer, and
    // looks as an untreated tooth, opaque and a little greyer than the treated tooth's enamel.
    {"neighbour", Material::Neighbour, 5, 4, {0.78, 0.80, 0.84}, {205, 208, 214},
     {2000.0, 0.0005, 0.15, 0.1},
     {{0.22, 0.22, 0.22}, {0.80, 0.80, 0.78}, {0.45, 0.45, 0.45}, 1.0, 40.0}},
};

// ---- 3. look-ups and derived lists -------------------------------------------------------------------

inline constexpr size_t kTissueCount = std::size(kTissueTable);

// The row of material m, or nullptr for empty and the spare codes.
constexpr const TissueRow* findTissue(Material m) {
  for (const TissueRow& row : kTissueTable)
    if (row.material == m) return &row;
  return nullptr;
}

// The row index of material m (what per-tissue arrays of kTissueCount use), or -1 for none.
constexpr int tissueIndex(Material m) {
  for (size_t i = 0; i < kTissueCount; ++i)
    if (kTissueTable[i].material == m) return int(i);
  return -1;
}

// The row index of each material code (-1 for empty and the spare codes), for per-voxel loops.
constexpr std::array<int, DS_MATERIAL_COUNT> tissueIndexByCode() {
  std::array<int, DS_MATERIAL_COUNT> out{};
  for (uint32_t m = 0; m < DS_MATERIAL_COUNT; ++m) out[m] = tissueIndex(Material(m));
  return out;
}
inline constexpr std::array<int, DS_MATERIAL_COUNT> kTissueIndexByCode = tissueIndexByCode();

// Every tissue's material, in table order.
constexpr std::array<Material, kTissueCount> tissueMaterials() {
  std::array<Material, kTissueCount> out{};
  for (size_t i = 0; i < kTissueCount; ++i) out[i] = kTissueTable[i].material;
  return out;
}
inline constexpr std::array<Material, kTissueCount> kTissues = tissueMaterials();

// Every tissue's material in draw order (rising draw_order).
constexpr std::array<Material, kTissueCount> tissuesInDrawOrder() {
  std::array<Material, kTissueCount> out{};
  for (const TissueRow& row : kTissueTable) out[size_t(row.draw_order)] = row.material;
  return out;
}

// Whether a tissue is sound tooth: every tissue of the treated tooth but caries, the lesion a caries
// removal is meant to take. The scores report and charge the healthy tissues that a cut removes; a
// neighbour cut is charged apart, as adjacent-tooth damage.
constexpr bool isHealthyTissue(Material m) { return m != Material::Caries && m != Material::Neighbour; }

// Whether a tissue belongs to the tooth being treated: every tissue but a neighbour. A tooth's
// extent, axis, volume and score are over these; a neighbour is only in the way.
constexpr bool isToothTissue(Material m) { return m != Material::Empty && m != Material::Neighbour; }

// The tissue names for messages and help: "enamel, dentin, pulp or caries"; with_empty appends
// "empty" as the last choice.
inline std::string tissueNameList(bool with_empty = false) {
  std::string out;
  const size_t n = kTissueCount + (with_empty ? 1 : 0);
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) out += i + 1 == n ? " or " : ", ";
    out += i < kTissueCount ? kTissueTable[i].name : "empty";
  }
  return out;
}

namespace tissue_table_internal {

constexpr bool drawOrderIsPermutation() {
  bool seen[kTissueCount] = {};
  for (const TissueRow& row : kTissueTable) {
    if (row.draw_order < 0 || size_t(row.draw_order) >= kTissueCount || seen[row.draw_order]) return false;
    seen[row.draw_order] = true;
  }
  return true;
}

constexpr bool codesAreTissues() {
  for (const TissueRow& row : kTissueTable)
    if (row.material == Material::Empty || uint32_t(row.material) >= DS_MATERIAL_COUNT) return false;
  return true;
}

}  // namespace tissue_table_internal

// A broken table fails the build, not a session: tissuesInDrawOrder indexes by draw_order, and a
// voxel holds 3 bits of material.
static_assert(tissue_table_internal::drawOrderIsPermutation(), "draw_order must number the rows 0..n-1");
static_assert(tissue_table_internal::codesAreTissues(), "a row's material is a tissue code 1..7");
static_assert(kTissueCount + 1 == DS_TISSUE_COUNT, "brick_layout.h's DS_TISSUE_COUNT counts empty and every row");

}  // namespace dentsim
