// Scripted preparations: pen paths that drill the tooth as a professional would, for the demo, the tasks' ideal cavities, tests and benchmarks.
//
// Each path is worked out from the volume itself (where the fossa is, where the caries lies), so it
// fits any tooth with the same anatomy, and is played by a ScriptedPen. Nothing here needs a
// device, a GPU or a window. The bur is held along +z, the crown's axis in today's convention.
// sim/novice_paths.h holds the faulty attempts that the score must tell apart from these.
//
// Contents
//   1. A class I occlusal cavity: an oval groove around the fossa
//   2. Caries removal: the caries and its access, layer by layer, inside the allowed zone
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "sim/sim_params.h"
#include "sim/surface_probe.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The treated tooth's box: tissueBox (sim/surface_probe.h) over the bricks that hold the tooth, not
// those that hold only an adjacent tooth (volume/tooth_frame.h, toothBricks), so that a neighbour
// does not move the crown's centre the paths start from. Without neighbours it is tissueBox.
TissueBox toothBox(const BrickVolume& volume, const VolumeFrame& frame);

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
  Vec3 search_offset_mm{0, 0, 0}; // moves that search's centre across the crown (x, y) [mm]; 0 for the fossa
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

// The preparation on this volume. Errors: no tissue under the bur anywhere in the fossa search,
// settings out of range.
Result<CavityPath> cavityPreparationPath(const BrickVolume& volume, const VolumeFrame& frame,
                                         const CavityPathSettings& settings = {});


// ---- 2. caries removal ------------------------------------------------------------------------------

// Caries removal as a careful dentist does it, with a round bur held vertically (tool axis +Z): the
// caries comes out together with the tissue above it along the bur's axis (its access, and the
// enamel the lesion undermines), and the bur stays inside the allowed zone that the score measures
// against (volume/cut_zone.h: that target and a `leeway_mm` shell around it).
//
// The tip's positions lie on a grid across the axis (`grid_mm`) in layers along it (`layer_mm`),
// from the top of the access down to the lesion's floor. A position is used when the whole ball
// of the bur fits the allowed zone (or the space without tissue) and holds target tissue; the
// layers are visited from the top, each row by row. Between positions that the ball cannot travel
// straight, the bur lifts clear of the tooth and comes down again.
//
// The pen presses `press_mm` below each position (with the 1 N/mm coupling, about press_mm
// newtons, a dentist's working force), so the bur always cuts at the full rate of the tissue it
// touches: it is metered, not driven to a target. Each position gets `margin` times the time the
// tissue it adds to the cut takes at the rates the parameter set gives (removal rate x hardness x
// the bur's ability, full speed), so the cut keeps to the plan whatever the press.
// A catalog bur's head radius [mm] (a tapered bur's widest, at its top); nullopt for other tools and unknown names.
std::optional<double> burHeadRadiusMm(const std::string& bur);

// The box of the caries voxels (fill > 0) [voxel indices, inclusive] and their volume [fill units].
struct LesionBox {
  uint32_t lo[3] = {UINT32_MAX, UINT32_MAX, UINT32_MAX};
  uint32_t hi[3] = {0, 0, 0};
  uint64_t fill = 0;
  bool empty() const { return lo[0] > hi[0]; }
};
LesionBox findLesion(const BrickVolume& volume);

struct CariesPathSettings {
  double bur_radius_mm = 0.0;     // radius of the round bur's head [mm]; 0: the bur's, from the tool catalog
  double grip_z_mm = 19.0;        // the grip point above the tip along the bur's axis [mm] (kBurGripLocal)
  double leeway_mm = 0.2;         // the ball may reach this far past the target [mm] (the task's leeway)
  double grid_mm = 0.2;           // between tip positions across the axis [mm]
  double layer_mm = 0.2;          // between layers of tip positions [mm]
  double press_mm = 1.2;          // the pen's target below each position [mm]
  double floor_overshoot_mm = 0.0;  // the pen presses at most this far below the column's lowest fitting tip [mm]
  // No position's ball comes nearer the pulp than this [mm]: over a deep lesion a careful dentist
  // leaves a layer of dentin on the pulp (selective removal) rather than expose it. The built-in
  // molar's lesion stays more than 1 mm from its pulp, so there it changes nothing.
  double pulp_margin_mm = 0.25;
  double margin = 1.2;            // a position lasts this times the time its tissue takes to cut
  double speed_mm_s = 4.0;        // fastest between neighbouring positions [mm/s]
  double hop_speed_mm_s = 10.0;   // lifted, from one part of a layer to another [mm/s]
  double turn_s = 0.3;            // kept at the end of each row before turning [s]
  double approach_mm = 1.0;       // start, hop and end this far above the tissue [mm]
  double hold_s = 0.1;            // above the start before the turbine starts, > 0 [s]
  double descent_s = 0.3;         // from above the tooth to the first position [s]
  double lift_s = 0.3;            // back up, pedal up [s]
  double sample_s = 0.01;         // at most this between path samples on a hop [s]
};

struct CariesPath {
  PenPath path;                  // drill samples
  Vec3 lesion_lo_mm, lesion_hi_mm;  // the box of the caries voxels [mm]
  double lesion_mm3 = 0.0;       // caries in the volume [mm^3]
  double planned_caries_mm3 = 0.0;   // caries inside the positions' balls [mm^3]
  double planned_healthy_mm3 = 0.0;  // enamel, dentin and pulp inside them [mm^3]
  int layers = 0;                // layers with at least one position
  int positions = 0;             // tip positions visited
  int hops = 0;                  // lifts from one part of a layer to another
  double duration_s = 0.0;       // time of the last sample [s]
  double cut_start_s = 0.0;      // pedal down [s]
  double cut_end_s = 0.0;        // pedal up [s]
};

// The removal on this volume, paced for `params` and the bur `bur`. Errors: no caries in the
// volume, settings out of range, a bur the parameter set does not know, no position that fits.
Result<CariesPath> cariesRemovalPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                     const std::string& bur, const CariesPathSettings& settings = {});

}  // namespace dentsim
