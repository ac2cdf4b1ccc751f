// Pacing a bur through a pocket as a careful dentist does: tip positions over an outline, layer by layer along the bur's axis, each held as long as the tissue it adds takes to cut, written as a pen path.
//
// The restorative preparations (sim/restorative_paths.h) describe a cavity as columns of tip
// positions across the bur's axis, each with the deepest height its tip may reach (its floor); this
// file turns them into a path. The bur may be held along any axis, so a class V cavity comes in
// from buccal as a class II comes in from occlusal.
//
// Contents
//   1. The bur's head, and frames along a bur's axis
//   2. Rays into the tooth: where the tissue begins, and which tissue
//   3. The pocket: columns and the path through them
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "sim/sim_params.h"
#include "sim/voxel_field.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. the head, and frames along the bur's axis -------------------------------------------------------

// The cutting head of a catalog bur in its own frame: axis +z, the tip at the origin.
struct BurHead {
  bool round = true;        // a ball on the tip; false: a flat-ended cylinder (fissure bur)
  double radius_mm = 0.5;   // [mm]
  double length_mm = 1.0;   // along the axis [mm]: the diameter for a ball, the cutting length for a cylinder
};
// The head of a bur of the tool catalog; a chamfer bur as a ball and a shoulder bur as a flat-ended
// cylinder, each of its tip radius (the narrowest part of the taper). An error names any other tool.
Result<BurHead> burHead(const std::string& bur);

// A frame whose third axis is the bur's (from the tip toward the handle): a point is
// origin + u e_u + v e_v + h axis, so h is a height along the bur and (u, v) a place across it [mm].
struct AxisFrame {
  Vec3 origin;
  Vec3 e_u{1, 0, 0}, e_v{0, 1, 0}, axis{0, 0, 1};  // unit, right-handed

  Vec3 at(double u, double v, double h) const { return origin + e_u * u + e_v * v + axis * h; }
  double height(const Vec3& p) const { return dot(p - origin, axis); }
  // The bur's frame as a rotation: its +z along `axis`.
  Quat rotation() const { return Quat::fromAxes(e_u, e_v, axis); }
  // `axis` normalized, e_u the unit part of `u_hint` across it (u_hint must not be parallel to it).
  static AxisFrame along(const Vec3& origin, const Vec3& axis, const Vec3& u_hint);
};

// ---- 2. rays into the tooth --------------------------------------------------------------------------------

// Where a ray first meets the tooth (the haptic field's surface, phi = 0, what the student feels).
class TissueRay {
 public:
  TissueRay(const BrickVolume& volume, const VolumeFrame& frame) : field_(volume, frame) {}

  struct Hit {
    double distance_mm = 0.0;  // along the ray from its start [mm]
    Vec3 point;                // the surface point [mm]
    Material material = Material::Empty;  // the tissue just inside it
  };
  // Marches from `from` along the unit `dir` one voxel at a time up to `max_mm`, then bisects the
  // crossing; nullopt when the ray meets no tissue. `from` should lie outside the tissue. A
  // neighbour (an adjacent tooth) is passed through: the hit is the treated tooth's surface.
  std::optional<Hit> first(const Vec3& from, const Vec3& dir, double max_mm);

 private:
  VoxelField field_;
};

// ---- 3. the pocket -------------------------------------------------------------------------------------------

// One column of tip positions: (u, v) across the axis on the pocket's grid, cut from the tissue's
// surface down to the tip height floor_h [mm along the axis].
struct PocketColumn {
  double u = 0.0, v = 0.0;  // [mm], multiples of the grid step
  double floor_h = 0.0;     // [mm]
};

struct PocketSettings {
  double grid_mm = 0.25;          // between columns [mm]; the columns' u and v are multiples of it
  double layer_mm = 0.25;         // between layers of tip positions along the axis [mm]
  double press_mm = 0.3;          // the pen's target this far past each position, toward the tip [mm]
  double floor_overshoot_mm = 0.0;  // ... but never more than this past the column's floor [mm]
  double margin = 1.0;            // a position lasts this times the time its new tissue takes to cut (the
                                  // ledger counts every voxel under the head whole, more than the bur takes)
  double speed_mm_s = 5.0;        // fastest between neighbouring positions [mm/s]
  double hop_speed_mm_s = 10.0;   // lifted clear, from one part of the pocket to another [mm/s]
  double turn_s = 0.1;            // kept at each row's end, where the trailing bur catches up [s]
  double approach_mm = 1.0;       // start, hops and end this far clear of the tissue [mm]
  double hold_s = 0.1;            // over the start before the turbine starts, > 0 [s]
  double lift_s = 0.3;            // back out, pedal up [s]
  double sample_s = 0.01;         // at most this between the samples of a long move [s]
  double grip_mm = 19.0;          // the grip point from the tip along the axis [mm] (kBurGripLocal)
};

struct PocketPath {
  PenPath path;                   // drill samples: grip pose (rotation: the bur along the frame's axis), pedal
  int positions = 0;              // tip positions visited (those that add tissue)
  int layers = 0;                 // layers with at least one position
  int hops = 0;                   // lifts from one part of a layer to another
  double planned_mm3 = 0.0;       // tissue inside the heads at the positions [mm^3]
  double cut_start_s = 0.0;       // pedal down [s]
  double cut_end_s = 0.0;         // pedal up [s]
  double duration_s = 0.0;        // the last sample [s]
};

// The path that cuts `columns` with `bur` held along `frame.axis`, paced for `params`: layers from
// the highest surface over the columns down to each column's floor, every row of a layer in turn
// (snaking), lifting clear where the straight way to the next position would leave the columns.
// Errors: no columns, settings out of range, a bur that is not a catalog bur or that `params` gives
// no cutting ability, no tissue under any column.
Result<PocketPath> pocketPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                              const std::string& bur, const AxisFrame& axis, const std::vector<PocketColumn>& columns,
                              const PocketSettings& settings = {});

}  // namespace dentsim
