// The tooth's frame: which way its crown, mesial and buccal sides face, found from the tissues or given, and the quarter turn that stands any tooth crown up.
//
// A scan or a mesh comes in whatever orientation its source had: the micro-CT molars lie with
// their crown toward -y. Everything downstream (the simulator's views, the score picture, the
// scripted paths, the bur standing upright) reads the crown as +z, so voxelize turns the grid by
// quarter turns until the crown axis lies nearest +z. A quarter turn moves whole voxels and loses
// nothing; the tilt left over (at most 45 degrees, a few in practice) is kept in the frame.
#pragma once

#include <array>
#include <optional>

#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

using QuarterTurn = std::array<int8_t, 9>;  // a signed permutation with determinant +1, row-major
inline constexpr QuarterTurn kNoTurn{1, 0, 0, 0, 1, 0, 0, 0, 1};

// What the caller knows of the axes, in the source's own coordinates (before any turn).
struct ToothAxesHint {
  std::optional<Vec3> crown;   // from the roots toward the crown; none: estimated from the enamel
  std::optional<Vec3> mesial;  // toward the mesial side; none: not known
  std::optional<Vec3> buccal;  // toward the buccal side; none: not known
  bool turn = true;            // false: record the axes but leave the grid as it is
};

// The quarter turn that brings `crown` nearest +z and, among those, `mesial` (when known) nearest
// -x; with mesial unknown, the smallest such turn.
QuarterTurn nearestQuarterTurn(const Vec3& crown, const std::optional<Vec3>& mesial);
// `turn` applied to a direction.
Vec3 turned(const QuarterTurn& turn, const Vec3& v);

// The turn that undoes `turn` (its transpose).
QuarterTurn inverseTurn(const QuarterTurn& turn);
// Where a simulation-frame point lay before voxelize turned the grid [mm]: the frame files for other
// tools are written in (export's labels, mesh's STL and PLY), so they overlay the source.
Vec3 sourcePointMm(const VolumeFrame& frame, const Vec3& p);
// The same for a direction (a normal).
Vec3 sourceDirection(const VolumeFrame& frame, const Vec3& d);

// Turns the volume's voxels about the grid's centre, and its frame with them: the scanner matrix
// and the source box follow, so an export still overlays the source; the tooth axes turn and
// `turn` composes into frame.tooth.turn.
void turnTooth(ToothVolume& tooth, const QuarterTurn& turn);

// The voxel box of each material's voxels with fill > 0 [voxel indices, inclusive]; an empty box
// (lo > hi) for a material that is absent. Index 0 is every tissue of the tooth together
// (isToothTissue): a neighbour has its own box at Material::Neighbour and is not in it.
struct VoxelBox {
  std::array<int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX};
  std::array<int64_t, 3> hi{INT64_MIN, INT64_MIN, INT64_MIN};
  bool empty() const { return lo[0] > hi[0]; }
};
std::array<VoxelBox, DS_MATERIAL_COUNT> tissueVoxelBoxes(const BrickVolume& volume);

// The box of the bricks that hold the tooth, as tissueBricks (brick_volume.h) but leaving out a
// brick whose tissue is all neighbour (an adjacent tooth). On a volume without neighbours it is
// tissueBricks exactly.
BrickBox toothBricks(const BrickVolume& volume);

// The middle of the occlusal surface [mm, simulation frame]: the centre of the tooth's extent
// across z, at the top of the tooth's tissue in that column (the fossa of a molar, the incisal
// edge's middle). Neighbour voxels are not the tooth's and are passed over. None for a volume
// without the tooth's tissue.
std::optional<Vec3> occlusalCentreMm(const ToothVolume& tooth);

// Finds the tooth's frame and stands it crown up: the crown axis from the hint or estimated from
// the enamel (volume/crown_estimate.h), the mesial and buccal directions from the hint, the
// nearest quarter turn applied, the occlusal centre measured. Errors: a given axis that is zero or
// not finite, mesial or buccal along the crown axis.
Status standToothUp(ToothVolume& tooth, const ToothAxesHint& hint);

// The frame of a tooth whose axes are known to be the convention's (the built-in molar): given,
// crown +z, mesial -x, buccal -y, with its occlusal centre.
void setConventionalAxes(ToothVolume& tooth);

// The occlusal centre of the tooth's frame, or measured when the file had none (files written
// before the frame existed).
Vec3 toothOcclusalCentreMm(const ToothVolume& tooth);

}  // namespace dentsim
