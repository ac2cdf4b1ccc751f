// Surface agreement: how much of the ideal cavity's surface the student's surface matches within a band (±0.2 mm), per wall, and the marks of the deviation picture.
//
// The ideal cavity's surface is sampled at every voxel face between a voxel the professional
// removed (the ideal cavity: initial tissue that the ideal no longer holds) and one the professional
// kept. A voxel counts as tissue when its fill is at least half (16 of 31), as the score picture's
// surface does. At each face, the signed deviation is the distance to the student's surface:
//   beyond (> 0): the student removed the kept voxel behind the face; the deviation is that voxel's
//                 distance to the nearest tissue the student kept
//   short  (< 0): the student kept the cavity voxel in front of the face; the deviation is minus that
//                 voxel's distance to the nearest voxel the student did not keep (cut, or air)
//   0           : the student's surface runs through the face
// Distances are exact Euclidean ones between voxel centres, computed on a box around the ideal
// cavity, and measured out to kDeviationReachMm beyond the band; a farther one counts at that cap
// (it is beyond the band either way). A face is within the band when |deviation| <= band_mm.
//
// Walls. Each face gets the direction its wall faces, into the cavity: the sum of the offsets of the
// cavity voxels minus those of the kept voxels in a window around it (kNormalRadius), which is a flat
// wall's own normal and rounds a stair-step wall to its slope. One rule names the wall: the
// direction the face faces most, among the insertion axis `a` (pointing out of the cavity, the way
// the bur comes in) and the tooth's axes across it (ToothAxes: mesial, buccal, crown):
//   - most along a (within 45 degrees of it, in a plane of a and a tooth axis): the floor,
//     "occlusal_floor" (a class V's axial wall is its floor);
//   - else the tooth's axis its part across a lies most along, the wall being named for the side of
//     the cavity it stands on: a wall facing distally stands on the mesial side, "mesial"; likewise
//     "distal", "buccal", "lingual", and for walls facing along the crown axis (a class V's)
//     "occlusal" (facing the roots) and "gingival".
// A tie (a face at an edge, exactly between two walls) goes to the wall the face itself turns toward
// (its own grid direction), so that a box cavity's walls are exactly its faces.
//
// Shares are by sample: every face is one voxel_mm^2 of stair-step surface, so area_mm2 is more
// than a smooth wall's where a wall slants across the grid (up to sqrt(3) times), the same for
// every class.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "core/rigid.h"
#include "eval/cut_marks.h"
#include "eval/score_image.h"
#include "volume/brick_volume.h"

namespace dentsim {

inline constexpr double kDefaultBandMm = 0.2;      // prepCheck users grade with ±0.2 mm [mm]
inline constexpr double kDeviationReachMm = 1.0;   // deviations are measured out to band + this [mm]
inline constexpr int kNormalRadius = 2;            // the wall direction's window: 2R x (2R+1)^2 voxels [voxels]

// The walls, in report order; kWallNames gives their report names.
enum class CavityWall : uint8_t { OcclusalFloor, Mesial, Distal, Buccal, Lingual, Occlusal, Gingival };
inline constexpr size_t kCavityWallCount = 7;
inline constexpr std::array<const char*, kCavityWallCount> kWallNames{"occlusal_floor", "mesial", "distal", "buccal",
                                                                      "lingual",        "occlusal", "gingival"};
// The first five are always reported; "occlusal" and "gingival" only when they hold samples.
inline constexpr size_t kAlwaysReportedWalls = 5;

// The picture's mark on an ideal wall voxel, as the score picture's paint; a voxel behind faces of
// several classes keeps the largest (short over beyond over within).
inline constexpr uint32_t kMarkWithin = kPaintGreen;
inline constexpr uint32_t kMarkBeyond = kPaintRed;
inline constexpr uint32_t kMarkShort = kPaintBlue;
static_assert(kMarkWithin < kMarkBeyond && kMarkBeyond < kMarkShort, "CutMarks keeps the larger mark");

struct WallAgreement {
  std::string wall;                // kWallNames' name
  uint64_t samples = 0;            // voxel faces of the ideal cavity's surface on this wall
  double area_mm2 = 0.0;           // samples x voxel_mm^2 [mm^2]
  uint64_t within = 0, beyond = 0, short_ = 0;  // samples by class; they sum to samples
  double within_percent = 0.0;     // of samples [%]; 0 when there are none
  double beyond_percent = 0.0;     // [%]
  double short_percent = 0.0;      // [%]
  double mean_deviation_mm = 0.0;  // mean signed deviation: > 0 beyond, < 0 short [mm]; 0 without samples
};

struct SurfaceAgreement {
  double band_mm = kDefaultBandMm;  // the tolerance band, ± [mm]
  double cap_mm = 0.0;              // deviations count at most this far: band_mm + kDeviationReachMm [mm]
  double voxel_mm = 0.0;            // voxel edge [mm]
  uint64_t samples = 0;             // voxel faces of the whole surface
  double area_mm2 = 0.0;            // [mm^2]
  uint64_t within = 0, beyond = 0, short_ = 0;
  double within_percent = 0.0, beyond_percent = 0.0, short_percent = 0.0;  // of samples [%]
  double mean_deviation_mm = 0.0;   // [mm]
  std::array<WallAgreement, kCavityWallCount> walls{};  // by CavityWall
  CutMarks marks;                   // per ideal wall voxel: kMarkWithin, kMarkBeyond or kMarkShort

  const WallAgreement& wall(CavityWall w) const { return walls[size_t(w)]; }
};

// Measures the student's final tooth against the ideal's cavity surface (see above).
// insertion_axis: grid axes, not zero (normalized here), pointing out of the cavity. band_mm >= 0.
// The volumes must share the level and the frame (errors name "initial", "final" or "ideal" and what
// differs). An ideal that removed no voxel (at the half-fill threshold) gives zero samples. Reads
// the bricks of the three volumes only inside a box around the ideal cavity.
Result<SurfaceAgreement> measureSurfaceAgreement(const ToothVolume& initial, const ToothVolume& final_,
                                                 const ToothVolume& ideal, const Vec3& insertion_axis,
                                                 double band_mm = kDefaultBandMm);

// The wall a face belongs to by the rule above: inward the face's direction into the cavity (any
// length, not zero), own its grid direction (the tie-breaker), axis the insertion axis (unit), tooth the
// tooth's axes (unit). Exposed for tests.
CavityWall cavityWallOf(const Vec3& inward, const Vec3& own, const Vec3& axis, const ToothAxes& tooth);

// {"band_mm", "samples", "area_mm2", "within_percent", "beyond_percent", "short_percent",
//  "mean_deviation_mm", "walls": {name: {"samples", "area_mm2", "within_percent", "beyond_percent",
//  "short_percent", "mean_deviation_mm"}}}: the five walls always, "occlusal" and "gingival" when they
//  hold samples.
nlohmann::ordered_json surfaceAgreementJson(const SurfaceAgreement& agreement);

}  // namespace dentsim
