// Layers for a tooth known only as one closed surface: the crown axis and mesial from its shape, the CEJ as its cervical waist, an enamel cap and a pulp by published proportions.
//
// Contents
//   1. ToothType: the tooth types whose proportions are known, parsed and named
//   2. LayerSynthOptions / LayerSynthReport
//   3. synthesizeLayers: one tissue in, enamel, dentin and pulp out
//   (the known answer, real layers against synthesized ones: volume/tooth_layer_compare.h)
//
// Most teeth reach a school as one closed surface (a CBCT segmentation, a tooth library, a scanned
// typodont): enamel and dentin are separate only in micro-CT work. The layers made here are
// synthesized, not measured; the caller says so wherever the tooth is shown (docs/VOLUME.md, "Layers
// from one surface", gives the method and its sources; docs/LAYER_SYNTHESIS.md the known-answer
// table against the micro-CT teeth).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. ToothType -------------------------------------------------------------------------------
enum class ToothType : uint8_t { Unknown, Molar, Premolar, Canine, Incisor };

// "molar", "premolar", "canine", "incisor"; "unknown" for Unknown.
const char* toothTypeName(ToothType type);
// The type named `name` (one of the four names above), or none.
std::optional<ToothType> parseToothType(const std::string& name);
// "molar, premolar, canine or incisor", for help and errors.
std::string toothTypeNames();

// ---- 2. options and report ----------------------------------------------------------------------
struct LayerSynthOptions {
  ToothType type = ToothType::Unknown;  // Unknown: guessed from the tooth's size and root count
  std::optional<Vec3> crown;            // grid axes, from the roots toward the crown; none: found from the shape
};

struct LayerSynthReport {
  ToothType type = ToothType::Unknown;  // the type used
  bool type_guessed = false;            // true: from size and roots, not the options
  Vec3 crown{0, 0, 1};                  // grid axes, unit, roots -> crown
  bool crown_found = false;             // true: from the shape (false: the options gave it)
  // Which end is mesial needs the arch and the side, which a lone shape never tells: `mesial` stays
  // none here (a caller that knows sets it), and only the line is reported.
  std::optional<Vec3> mesial;           // grid axes, unit, perpendicular to crown; none: not known
  std::optional<Vec3> mesiodistal;      // grid axes, unit, perpendicular to crown: the mesiodistal line,
                                        //   its sign arbitrary; none: the shape does not tell it for this type
  int roots = 0;                        // roots counted below the furcation
  double tooth_length_mm = 0.0;         // apex to cusp tip along the crown axis [mm]
  double cej_mm = 0.0;                  // the CEJ's height above the apex along the crown axis [mm]
  double furcation_mm = 0.0;            // where the roots part, above the apex [mm]; 0: one root
  double enamel_cusp_mm = 0.0;          // the enamel's thickness over the cusps as applied [mm]
  double enamel_fissure_mm = 0.0;       // ... in the fissures [mm]
  double enamel_mm3 = 0.0, dentin_mm3 = 0.0, pulp_mm3 = 0.0;  // the layers made [mm^3]
  // What was found and made, one line each, for `voxelize` to print and the tooth's source_note to
  // keep (the first says the layers are synthesized).
  std::vector<std::string> lines;
};

// ---- 3. synthesizeLayers ------------------------------------------------------------------------
// What synthesizeLayers costs per voxel of the tooth's bounding box, for voxelize's plan: its dense
// local grids (masks, depths, the smoothed shape), as measured on the chai3d molar at levels 9 and
// 10 (34 and 273 million box voxels: 0.9 GB and 11 s, 6.6 GB and 88 s on a 2-core machine), rounded
// up so that the plan errs high.
inline constexpr double kLayerSynthBytesPerBoxVoxel = 28.0, kLayerSynthSecondsPerBoxVoxel = 0.35e-6;

// `volume` holds one tooth voxelized from one closed surface: every tooth voxel one tissue (any
// material; partial voxels keep their fill). Its voxels become enamel (a cap over the crown down to
// the CEJ), pulp (chamber and canals) and dentin (the rest), in place. `voxel_mm` is the grid's
// voxel edge [mm]. Errors (one line, the volume untouched): no tooth voxels, a tooth too small for
// layers at this voxel size, a cancel. Memory: about 14 bytes a voxel of the tooth's bounding box
// at the peak (a level-9 molar: about 1 GB), freed on return.
Result<LayerSynthReport> synthesizeLayers(BrickVolume& volume, double voxel_mm, const LayerSynthOptions& options,
                                          Interrupter* progress = nullptr);

}  // namespace dentsim
