// Scripted preparations: pen paths that drill the tooth as a professional would, for the demo, the tasks' ideal cavities, tests and benchmarks.
//
// Each path is worked out from the volume itself (where the fossa is, where the caries lies), so it
// fits any tooth with the same anatomy, and is played by a ScriptedPen. Nothing here needs a
// device, a GPU or a window.
//
// Contents
//   1. A class I occlusal cavity: an oval groove around the fossa
//   2. Caries removal: layers over the lesion, paced by what they remove
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "sim/sim_params.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The box of the bricks holding any tissue, simulation frame [mm]; empty when there is none. Whole
// bricks, so it is up to a brick wider than the tissue on each side.
struct TissueBox {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL};
  Vec3 hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  bool empty() const { return lo.x > hi.x; }
  Vec3 centre() const { return (lo + hi) * 0.5; }
};
TissueBox tissueBox(const BrickVolume& volume, const VolumeFrame& frame);

// ---- 1. a class I cavity --------------------------------------------------------------------------

// A class I occlusal preparation with a round bur held vertically (tool axis +Z, rotation identity).
// The fossa is where the bur rests lowest near the crown's centre; the outline is an oval of
// `oval_x_mm` x `oval_y_mm` (the bur tip's path) around it. The pen starts `approach_mm` above the
// bur's resting height over the oval's +x end, the pedal goes down, and the pen's target comes down
// to `press_mm` below that resting height (the coupling spring is 1 N/mm by default, so about
// press_mm newtons), stays `dwell_s`, then traces the oval `laps` times at `speed_mm_s`, following
// the untouched surface press_mm below the resting height and sinking `step_down_mm` more per lap;
// then pedal up and lift. The bur removes tissue at a rate that does not depend on the force, so
// a bur held still would sink to the target: moving on, it cuts a groove a little deeper each lap.
struct CavityPathSettings {
  double bur_radius_mm = 0.5;     // radius of the round bur's head [mm] (round_bur_010)
  double grip_z_mm = 19.0;        // the grip point above the tip along the bur's axis [mm] (kBurGripLocal)
  double approach_mm = 1.0;       // start this far above the resting height [mm]
  double press_mm = 1.5;          // pen target below the resting height [mm]
  double step_down_mm = 0.15;     // extra depth of the target per lap, ramped along the outline [mm]
  double oval_x_mm = 2.0;         // outline extent along x, mesiodistal [mm] (the bur tip's path)
  double oval_y_mm = 1.2;         // outline extent along y, buccolingual [mm]
  double speed_mm_s = 2.0;        // along the outline [mm/s]
  double laps = 2.0;              // laps of the outline, > 0 (fractions allowed)
  double hold_s = 0.1;            // above the outline's start before the turbine starts, > 0 [s]
  double descent_s = 0.3;         // from the approach height to the pressed target [s]
  double dwell_s = 0.1;           // pressed at the outline's start before moving [s]
  double lift_s = 0.2;            // back up to approach_mm above the resting height, pedal up [s]
  double sample_s = 0.01;         // between path samples [s]; the scripted pen interpolates
  double fossa_search_mm = 1.0;   // the fossa: the lowest resting point within this of the crown's centre [mm]
  double fossa_grid_mm = 0.1;     // spacing of that search [mm]
};

struct CavityPath {
  PenPath path;                  // drill samples: grip pose (tip + grip_z along +Z), pedal
  Vec3 crown_centre_mm;          // centre of the tissue bricks' x,y extent, at their top (z) [mm]
  Vec3 fossa_mm;                 // the bur tip resting over the fossa [mm]
  double duration_s = 0.0;       // time of the last sample [s]
  double cut_start_s = 0.0;      // pedal down [s]
  double cut_end_s = 0.0;        // pedal up [s]
  double outline_mm = 0.0;       // length of one lap of the oval [mm]
};

// The bur tip's lowest height [mm] when a ball of `radius_mm` comes down vertically over (x, y) onto
// the volume's tissue (fill over one half), from above the tissue; nullopt when it meets none.
std::optional<double> restingTipHeight(const BrickVolume& volume, const VolumeFrame& frame, double x_mm, double y_mm,
                                       double radius_mm);

// The preparation on this volume. Errors: no tissue under the bur anywhere in the fossa search,
// settings out of range.
Result<CavityPath> cavityPreparationPath(const BrickVolume& volume, const VolumeFrame& frame,
                                         const CavityPathSettings& settings = {});


// ---- 2. caries removal ------------------------------------------------------------------------------

// Caries removal from above with a round bur held vertically (tool axis +Z), as a professional
// would pace it. The lesion is the box of the volume's caries voxels; the bur opens it from the
// occlusal side in layers of `layer_mm`, each layer a back-and-forth raster over the box (lines
// along x, `line_spacing` radii apart, reaching `overreach` radii past the lines' ends), the last
// layer with the tip at the lesion's floor. Layers are paced by what they remove: a pass takes at
// least its tissue's volume over the rate the parameter set gives (removal rate x hardness x the
// bur's ability, full speed), times `margin`, so the bur keeps up with its target and presses
// lightly. An opening wide enough for the deepest layer is cut from the top: healthy tissue over
// the lesion goes too, as it does in a clinic.
struct CariesPathSettings {
  double bur_radius_mm = 0.9;     // radius of the round bur's head [mm] (round_bur_018)
  double grip_z_mm = 19.0;        // the grip point above the tip along the bur's axis [mm] (kBurGripLocal)
  double approach_mm = 1.0;       // start this far above the tissue's top over the lesion [mm]
  double layer_mm = 0.25;         // depth of one layer [mm]
  double line_spacing = 1.0;      // between raster lines [bur radii]
  double overreach = 0.4;         // the lines' ends stop this far inside the box's edges [bur radii]
  double speed_mm_s = 3.0;        // fastest along a pass [mm/s]
  double margin = 1.6;            // a pass lasts this times the time its tissue takes to cut
  double hold_s = 0.1;            // above the start before the turbine starts, > 0 [s]
  double descent_s = 0.3;         // from the approach height to the first layer [s]
  double lift_s = 0.3;            // back up, pedal up [s]
  double sample_s = 0.01;         // between path samples [s]
};

struct CariesPath {
  PenPath path;                  // drill samples
  Vec3 lesion_lo_mm, lesion_hi_mm;  // the box of the caries voxels [mm]
  double lesion_mm3 = 0.0;       // caries in the volume [mm^3]
  int layers = 0;
  double duration_s = 0.0;       // time of the last sample [s]
  double cut_start_s = 0.0;      // pedal down [s]
  double cut_end_s = 0.0;        // pedal up [s]
};

// The removal on this volume, paced for `params` and the bur `bur`. Errors: no caries in the
// volume, settings out of range, a bur the parameter set does not know.
Result<CariesPath> cariesRemovalPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                     const std::string& bur, const CariesPathSettings& settings = {});

}  // namespace dentsim
