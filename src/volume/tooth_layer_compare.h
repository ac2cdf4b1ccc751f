// The known answer for synthesized layers (docs/LAYER_SYNTHESIS.md): a layered tooth made one closed shape, and synthesized layers compared with the real ones in the same grid.
#pragma once

#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The whole tooth as one closed shape: every tooth tissue of `layered` (pulp and caries included)
// becomes dentin with its fill kept, so the shape is closed and synthesizeLayers sees what a
// surface would give it.
BrickVolume wholeToothShape(const BrickVolume& layered);

// Real layers against synthesized ones in the same grid. Caries in `real` counts as dentin.
struct LayerComparison {
  double dice_enamel = 0.0, dice_dentin = 0.0, dice_pulp = 0.0;  // 2|A and B| / (|A| + |B|), voxels with fill > 0
  // Mean enamel thickness: enamel volume over the enamel's outer area (voxel faces toward empty) [mm].
  double enamel_mm_real = 0.0, enamel_mm_synth = 0.0;
  double enamel_error_mm = 0.0;  // |synth - real| of the mean thickness [mm]
  Vec3 measured_crown{0, 0, 1};  // estimateCrown on the real layers (volume/crown_estimate.h), unit
  double axis_angle_deg = 0.0;   // between measured_crown and the synthesized report's crown [degrees]
};
LayerComparison compareLayers(const BrickVolume& real, const BrickVolume& synth, double voxel_mm,
                              const Vec3& synth_crown);

}  // namespace dentsim
