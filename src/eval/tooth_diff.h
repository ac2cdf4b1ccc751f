// ToothDiff: the voxel comparison behind the scores: removed and remaining per tissue, and how the cut falls in the target, the leeway and the container, in fill units.
//
// With fill, the paper's sets become amounts. Per voxel, in fill units (1/31 voxel), with
// i = initial fill, r = min(final fill, i), and c the voxel's share of the target:
//   removed = i - r
//   c = i - min(ideal fill, i) with an ideal (the ideal cavity); without one, c = i for a voxel of
//       the caries or its access along the insertion axis, else 0
//   target removed = min(removed, c)       under-cut = c - target removed = max(0, r - k)
//   beyond the target = removed - min(removed, c) = max(0, k - r) with an ideal: the over-cut
// The rest of the voxel, i - c, lies in the leeway when the voxel is within leeway_mm of a target
// voxel (a target voxel is at distance 0), else in the container. Each amount is filed under the
// voxel's initial material. docs/SCORING.md derives the binary reductions and explains the zones
// and pulp exposure.
//
// A neighbour (an adjacent tooth, Material::Neighbour) is filed under its own row but is not the
// tooth: it is never target, total() and healthy() leave it out, and what was cut of it is
// adjacent(), scored as its own deduction (docs/SCORING.md, "Adjacent teeth").
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "eval/cut_marks.h"
#include "volume/cut_zone.h"
#include "volume/brick_volume.h"
#include "volume/crown_estimate.h"
#include "volume/tissue_table.h"

namespace dentsim {

// The tissues in report order: the tissue table's.
inline constexpr std::array<Material, kTissueCount> kScoredTissues = kTissues;

// Sums over the voxels of one initial tissue [fill units; 31 = one voxel]. initial = target + leeway
// + container, and removed = the sum of the three removed amounts.
struct TissueAmounts {
  uint64_t initial = 0;            // sum of i
  uint64_t remaining = 0;          // sum of r
  uint64_t removed = 0;            // sum of i - r
  uint64_t target = 0;             // sum of c: the ideal cavity, or the caries and its access
  uint64_t target_removed = 0;     // sum of min(removed, c)
  uint64_t leeway = 0;             // sum of i - c over voxels within the leeway of the target
  uint64_t leeway_removed = 0;     // removed beyond c in those voxels
  uint64_t container = 0;          // sum of i - c over the other voxels
  uint64_t container_removed = 0;  // removed beyond c in those voxels

  uint64_t undercut() const { return target - target_removed; }           // target left standing
  uint64_t overcut() const { return leeway_removed + container_removed; }  // removed beyond the target
  TissueAmounts& operator+=(const TissueAmounts& o);
  bool operator==(const TissueAmounts&) const = default;
};

// What the target is.
enum class TargetKind {
  IdealCavity,    // what the professional's final tooth removed from the initial one
  CariesAccess,   // the caries, and every voxel on the line from it along the insertion axis
};

struct ToothDiff {
  double voxel_mm = 0.0;                    // voxel edge [mm]
  bool has_ideal = false;                   // an ideal was given; the target is its cavity
  TargetKind target_kind = TargetKind::CariesAccess;
  Vec3 access_axis{0, 0, 1};                // CariesAccess: the insertion axis (unit, grid axes)
  double leeway_mm = 0.0;                   // the leeway around the target [mm]
  std::array<TissueAmounts, kTissueCount> tissues{};  // by kScoredTissues' order
  bool pulp_exposed = false;                // some pulp lost fill, or lies open to a cut-out neighbour
  uint64_t exposed_pulp_voxels = 0;         // pulp voxels that did either
  CrownEstimate crown;                      // the initial tooth's crown direction
  uint64_t target_in_crown_half = 0;        // target units whose voxel centre lies in the crown half
  CutMarks beyond_target;                   // per voxel: the tooth's tissue removed beyond the target (the over-cut with an ideal)
  CutMarks healthy_outside_zone;            // per voxel: healthy tissue (isHealthyTissue) removed in the container
  CutMarks adjacent_removed;                // per voxel: neighbour removed, anywhere

  const TissueAmounts& tissue(Material m) const;  // m one of kScoredTissues
  TissueAmounts total() const;                    // over the tooth's tissues (isToothTissue): not a neighbour
  TissueAmounts healthy() const;                  // over the healthy tissues (isHealthyTissue): not caries, not a neighbour
  const TissueAmounts& adjacent() const;          // the neighbour's row: adjacent teeth; initial 0 when there is none
  // Fill units to [mm^3]: voxel_mm^3 / 31 per unit.
  double mm3(uint64_t units) const;
};

// How the volumes are named in errors: file names, or the roles by default.
struct DiffNames {
  std::string initial = "initial";
  std::string final_ = "final";
  std::string ideal = "ideal";
};

// The zone the diff measures against.
struct ZoneOptions {
  double leeway_mm = 0.2;        // >= 0
  Vec3 access_axis{0, 0, 1};     // without an ideal: the insertion axis (not zero; normalized here)
};

// Ok when b lies on a's grid: the same octree level, voxel size and origin (sub-nanometre differences
// are rounding); otherwise an error naming b (by b_name) and what differs from a (by a_name).
Status checkSameFrame(const ToothVolume& a, const std::string& a_name, const ToothVolume& b, const std::string& b_name);

// Compares the initial tooth with the student's final one and, when `ideal` is given, with the
// professional's final one (the target is then what that removed from the initial tooth; without
// it, the caries and its access). Volumes must share the level and the frame (voxel size and
// origin): otherwise an error naming the volume (by `names`) and what differs.
// Brick by brick: a brick equal in all volumes and away from the target costs one comparison and
// contributes analytically.
Result<ToothDiff> compareTeeth(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                               const ZoneOptions& zone, const DiffNames& names = {});

}  // namespace dentsim
