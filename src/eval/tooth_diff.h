// ToothDiff: the voxel comparison behind the scores: removed, remaining, ideal cavity, under-cut and over-cut, per tissue, in fill units.
//
// With fill, the paper's sets become amounts. Per voxel, in fill units (1/31 voxel), with
// i = initial fill, r = min(final fill, i), k = min(ideal fill, i):
//   removed = i - r            ideal cavity c = i - k
//   under-cut = max(0, r - k)  (left standing where the ideal removes: C AND R for fills 0/31)
//   over-cut  = max(0, k - r)  (cut where the ideal keeps: I AND NOT R AND NOT C for fills 0/31)
// so removed = c - under + over. Each amount is filed under the voxel's initial material.
// docs/SCORING.md derives the binary reductions and explains the leeway split and pulp exposure.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/result.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The four tissues in report order.
inline constexpr std::array<Material, 4> kScoredTissues = {Material::Enamel, Material::Dentin, Material::Pulp,
                                                           Material::Caries};

// Sums over the voxels of one initial tissue [fill units; 31 = one voxel].
struct TissueAmounts {
  uint64_t initial = 0;        // sum of i
  uint64_t remaining = 0;      // sum of r
  uint64_t removed = 0;        // sum of i - r
  uint64_t ideal_cavity = 0;   // sum of i - k (0 without an ideal)
  uint64_t undercut = 0;       // sum of max(0, r - k) (0 without an ideal)
  uint64_t overcut = 0;        // sum of max(0, k - r) (0 without an ideal)
  uint64_t overcut_near = 0;   // over-cut in voxels within leeway_mm of an ideal-cavity voxel
  uint64_t overcut_gross = 0;  // the rest of the over-cut: overcut = near + gross
  TissueAmounts& operator+=(const TissueAmounts& o);
  bool operator==(const TissueAmounts&) const = default;
};

struct ToothDiff {
  double voxel_mm = 0.0;                    // voxel edge [mm]
  bool has_ideal = false;                   // an ideal was given
  double leeway_mm = 0.0;                   // the near/gross split's distance [mm]
  std::array<TissueAmounts, 4> tissues{};   // by kScoredTissues' order
  bool pulp_exposed = false;                // some pulp lost fill, or lies open to a cut-out neighbour
  uint64_t exposed_pulp_voxels = 0;         // pulp voxels that did either

  const TissueAmounts& tissue(Material m) const;  // m one of kScoredTissues
  TissueAmounts total() const;                    // over all four tissues
  // Fill units to [mm^3]: voxel_mm^3 / 31 per unit.
  double mm3(uint64_t units) const;
};

// How the volumes are named in errors: file names, or the roles by default.
struct DiffNames {
  std::string initial = "initial";
  std::string final_ = "final";
  std::string ideal = "ideal";
};

// Compares the initial tooth with the student's final one and, when `ideal` is given, with the
// professional's final one (the ideal cavity is what that removed from the initial tooth).
// Volumes must share the level and the frame (voxel size and origin): otherwise an error naming
// the volume (by `names`) and what differs. leeway_mm >= 0 (Euclidean, between voxel centres).
// Brick by brick: a brick equal in all volumes costs one comparison and contributes analytically.
Result<ToothDiff> compareTeeth(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                               double leeway_mm, const DiffNames& names = {});

}  // namespace dentsim
