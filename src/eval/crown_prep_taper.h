// The crown preparation's taper measures: total occlusal convergence in four planes, height, width and their ratio, from the voxels.
//
// An examiner grades a full-crown preparation by its shape in sections through the path of
// insertion (Goodacre et al. 2001, "Tooth preparations for complete crowns", J Prosthet Dent
// 85:363-376): the total occlusal convergence (TOC) of opposing axial walls, 10 to 20 deg; an
// occlusocervical height of at least 4 mm on molars and 3 mm on other teeth; and a height/width
// ratio of at least 0.4. These are measured here the way a section would show them.
//
// How. Heights are along the insertion axis from the grid origin, at voxel centres ((i + 0.5) *
// voxel_mm on each grid axis). Each plane holds the axis and one direction across it; the plane
// passes through the centroid of the tooth voxels in the gingival band (the margin up 2 mm). In a
// slab 1.5 voxels thick around the plane, each height bin (one voxel tall) gives the outermost tooth
// voxel on either side: the section's profile. Examiners read the axial wall, not the finish line's
// curve: a chamfer's rounded foot at the band's bottom runs outward far faster than the wall, so
// the fit starts above it (where the profile leaves the line of the band's upper half by more than
// kWallDepartureVoxels). A least-squares line through each wall's remaining profile gives that
// wall's inclination to the axis; the TOC is the sum of the two (the angle
// between the lines when both converge; a wall that leans out, an undercut, counts negative).
// Only tooth tissues count (isToothTissue): a neighbour beside the tooth changes nothing.
#pragma once

#include <array>

#include "core/result.h"
#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

// Goodacre 2001's figures, for callers that grade against them.
inline constexpr double kTocMinDeg = 10.0;              // least recommended TOC [deg]
inline constexpr double kTocMaxDeg = 20.0;              // most recommended TOC [deg]
inline constexpr double kMinHeightMolarMm = 4.0;        // least occlusocervical height, molars [mm]
inline constexpr double kMinHeightOtherMm = 3.0;        // least height, incisors and premolars [mm]
inline constexpr double kMinHeightWidthRatio = 0.4;     // least height / width [-]

// The axial walls are fitted over this band above the margin [mm]: the gingival part, where
// retention comes from and where examiners read the taper (the occlusal part is rounded off).
inline constexpr double kTaperBandMm = 2.0;
// The axial wall ends where the finish line's rounding begins: walking down from the band's upper
// half, a height whose profile lies farther than this from the upper half's line [voxels] is the
// chamfer's (or shoulder's) foot, and it and all below are left out of the fit. One voxel is the
// profile's own rounding on a straight wall; a 0.5 mm chamfer departs by more within its lower
// part, so the foot's outward curve cannot read as a steeper wall. Only an upper half that
// converges, no steeper than 45 deg, is such a wall: one leaning out or stepped (an undercut) is
// fitted over the whole band, so its reading is not that of its step alone.
inline constexpr double kWallDepartureVoxels = 0.5;
// A wall's line needs at least this many heights with tooth on that side: fewer is not a line but a
// step (a preparation shorter than a few voxels, or a voxel far too coarse for 2 mm).
inline constexpr int kMinWallPoints = 5;

// One section through the insertion axis.
struct TaperPlane {
  const char* name = "";     // "mesiodistal", "buccolingual", "diagonal+45", "diagonal-45"
  Vec3 direction{};          // the in-plane direction across the axis, unit, grid axes
  double toc_deg = 0;        // total occlusal convergence: wall_deg[0] + wall_deg[1] [deg]
  double wall_deg[2] = {0, 0};  // each wall's inclination to the axis, + converging toward occlusal;
                                // [0] on the +direction side (mesial in the mesiodistal plane), [1] opposite [deg]
  int points[2] = {0, 0};    // heights fitted on each wall (one per voxel-tall bin in the band, less the foot)
  int foot_skipped[2] = {0, 0};  // heights at the band's bottom left out as the finish line's rounding
};

// The preparation's shape as a section would show it.
struct CrownPrepShape {
  // mesiodistal (axis and `mesial`), buccolingual (axis x mesial), then the diagonals at +45 and
  // -45 deg from mesial toward axis x mesial.
  std::array<TaperPlane, 4> planes{};
  double height_mm = 0;    // from the margin to the highest tooth voxel's top along the axis [mm]
  double width_md_mm = 0;  // wall to wall at the margin, outer voxel faces, mesiodistal plane [mm]
  double width_bl_mm = 0;  // the same in the buccolingual plane [mm]
  // height / max(width_md, width_bl) [-]. Goodacre's 0.4 is height over width; the larger width is
  // taken, the stricter reading, so a long oval preparation cannot pass on its narrow side.
  double height_width_ratio = 0;
};

// Measures the prepared tooth in `volume` (voxel edge voxel_mm > 0 [mm]). insertion_axis points
// occlusally, grid axes, any length > 0 (normalized here); mesial is any direction not along the
// axis (its part across the axis is used). margin_height_mm: the finish line's height along the
// axis from the grid origin [mm], the lowest prepared height. Errors, one line each: a zero or
// non-finite axis, mesial along the axis, no tooth voxels, the margin outside the tooth, no tooth
// at the margin in a plane, fewer than kMinWallPoints on a wall.
Result<CrownPrepShape> measurePrepShape(const BrickVolume& volume, double voxel_mm, const Vec3& insertion_axis,
                                        const Vec3& mesial, double margin_height_mm);

}  // namespace dentsim
