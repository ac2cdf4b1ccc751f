// A phantom scan from a segmented tooth: each tissue's grey value, the scanner's blur and its noise, so that a known answer can be scanned, read back and segmented.
//
// Contents
//   1. ScanModel: the values and the imaging model
//   2. simulateScan: labels -> grey values
//
// The model, stated once (docs/PATIENT_SCANS.md quotes it):
//   - each voxel takes its tissue's value (in HU by default: air -1000, pulp 40, caries 700, dentin
//     1700, enamel 2900; published CT figures for dentin and enamel run about 1500-2000 and 2500-3200);
//   - the scanner's point spread is a Gaussian of standard deviation blur_mm, applied separably along the
//     three axes (each axis in its own pitch), with the border value repeated;
//   - then independent Gaussian noise of standard deviation noise (in the value's unit) is added to
//     every voxel, from a seeded generator, so a phantom is the same on every machine.
// Not modelled: beam hardening (cupping, streaks near enamel), metal artefacts, ring artefacts, and the
// partial filling of a voxel by two tissues beyond what the blur gives.
#pragma once

#include <cstdint>
#include <map>

#include "core/interrupter.h"
#include "core/result.h"
#include "io/grey_image.h"
#include "io/nifti_labels.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. ScanModel ----------------------------------------------------------------------------
struct ScanModel {
  // Grey value of each tissue (Material code: empty, enamel, dentin, pulp, caries) [unit].
  std::array<float, DS_MATERIAL_COUNT> value{-1000.0f, 2900.0f, 1700.0f, 40.0f, 700.0f};
  double blur_mm = 0.04;    // standard deviation of the point spread [mm]; 0: none
  double noise = 100.0;     // standard deviation of the added noise [unit]; 0: none
  uint32_t seed = 1;        // the noise generator's seed
  GreyUnit unit = GreyUnit::Hounsfield;
};

// ---- 2. simulateScan -------------------------------------------------------------------------
// Labels (mapped to tissues by `map`; a label not in it is an error naming it, label 0 is empty) into
// grey values on the labels' own grid and geometry. `pitch_mm`, when positive, replaces the labels'
// pitch (isotropic) as voxelize's --voxel-size does. Memory: the floats (4 bytes a voxel) and one
// line of scratch per axis. Errors: one line naming `where`.
Result<GreyImage> simulateScan(const LabelImage& labels, const std::map<int32_t, Material>& map, const ScanModel& model,
                               double pitch_mm = 0.0, const std::string& where = "labels",
                               Interrupter& interrupter = nullInterrupter());

}  // namespace dentsim
