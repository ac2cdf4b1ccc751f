// Probing a tooth from above for the scripted paths: the box of its tissue, and the height at which the surface or a round bur coming down meets it.
#pragma once

#include <cmath>
#include <optional>

#include "core/rigid.h"
#include "core/volume_frame.h"
#include "sim/voxel_field.h"
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
// The box of bricks `bricks` in the simulation frame [mm] (empty for none): what tissueBox and
// scripted_paths.h's toothBox measure.
TissueBox brickBoxMm(const BrickBox& bricks, const VolumeFrame& frame);

// Column probes of one volume: the topmost crossing of the haptic field's surface (phi = 0, what the
// student feels and sees), searched downward from above the tissue one voxel at a time.
class SurfaceProbe {
 public:
  SurfaceProbe(const BrickVolume& volume, const VolumeFrame& frame, const TissueBox& box);

  // Height [mm] of the surface in the column through (x, y); nullopt when the column holds no tissue.
  std::optional<double> surface(double x, double y);
  // The tip height [mm] of a ball of radius r [mm] coming down over (x, y): the highest of the
  // columns under it, each lowered by the ball's sag at its distance from the axis.
  std::optional<double> restingTip(double x, double y, double r);

 private:
  VoxelField field_;
  double top_mm_;
  double bottom_mm_;
};

// Where a ball of radius r [mm] coming down from +z rests lowest on a grid of grid_mm within search_mm
// of (x, y), scanned row by row (y outer, x inner) and keeping the first of equal heights: the
// fossa when (x, y) is the crown's centre. nullopt when no column under the search holds tissue.
std::optional<Vec3> lowestRestingTip(SurfaceProbe& probe, double x, double y, double r, double search_mm, double grid_mm);

// The bur tip's lowest height [mm] when a ball of `radius_mm` comes down vertically over (x, y) onto
// the volume's tissue (fill over one half), from above the tissue; nullopt when it meets none.
std::optional<double> restingTipHeight(const BrickVolume& volume, const VolumeFrame& frame, double x_mm, double y_mm,
                                       double radius_mm);

}  // namespace dentsim
