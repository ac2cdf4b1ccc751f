// The crown preparation's finish line: found as the boundary between prepared and unprepared surface, with its width, continuity, smoothness and height over the CEJ.
//
// Heights are along the insertion axis from the grid origin, voxel centres at (i + 0.5) * voxel_mm
// on each grid axis (as eval/crown_prep_taper.h). The line is read in kMarginSectors equal angular
// sectors around the insertion axis, starting at mesial and turning toward axis x mesial (buccal).
// Implemented in eval/crown_prep_margin.cpp; the rules (what is prepared surface, how the width is
// read, which roughness) are that file's opening comment and docs/CROWN_PREPARATION.md's.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

inline constexpr int kMarginSectors = 72;  // 5 degrees each

struct MarginSector {
  bool found = false;        // the sector has a finish line
  double height_mm = 0;      // the line's height along the axis from the grid origin: its lowest voxel's face toward removed tooth [mm]
  double width_mm = 0;       // the step's width across the axis there [mm]
  std::optional<double> cej_height_mm;  // the original enamel's cervical edge in the sector, when the tooth has enamel [mm]
};

struct MarginLine {
  std::array<MarginSector, kMarginSectors> sectors{};
  int found_sectors = 0;           // sectors with a line
  int gaps = 0;                    // runs of sectors without a line, around the circle (0: continuous; no line at all: 1)
  double gap_share = 0;            // sectors without a line / kMarginSectors [0..1]
  double mean_width_mm = 0;        // over the sectors found [mm]
  double min_width_mm = 0;         // [mm]
  double roughness_mm = 0;         // the line's height wander, the RMS named in the .cpp [mm]
  double mean_height_mm = 0;       // over the sectors found, from the grid origin [mm]
  double lowest_height_mm = 0;     // the lowest sector's height [mm]
  std::optional<double> mean_above_cej_mm;  // mean of (height - CEJ) over sectors with both [mm]
  // The prepared tooth's voxels on the line, as reductionVoxelKey (eval/crown_prep_reduction.h), for the picture.
  std::vector<uint64_t> line_voxels;
};

// original and prepared share a grid; insertion_axis points occlusally and mesial is across it (both
// grid axes, normalized here; mesial's part along the axis dropped). Errors, one line each: different
// grids, no tooth in either, a bad axis or mesial. A tooth with nothing prepared is not an error: its
// line has no sector found.
Result<MarginLine> findMargin(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                              const Vec3& insertion_axis, const Vec3& mesial);

}  // namespace dentsim
