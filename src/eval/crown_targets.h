// The full-crown preparation's targets by the crown's material and the finish line: the bands `task new --kind crown` writes into a task and a crown task file's missing keys take.
//
// Contents
//   1. The finish lines: each one's burs and the material's width it takes
//   2. The materials: each one's reductions and margin widths, with their sources
//   3. What every material shares: convergence, height, the margin's place, undercuts
//   4. Look-ups, the targets of a finish and a material, and lists for messages
//
// Header-only, like eval/task_kinds.h, so that the CLI tests can hold `task new` to the same rows
// without linking eval. The figures are starting points from the teaching literature; a teacher
// changes any of them in the task file (docs/SCORING.md, section 10).
#pragma once

#include <cstddef>
#include <iterator>
#include <string>
#include <string_view>

#include "core/result.h"
#include "eval/task.h"
#include "eval/task_kinds.h"

namespace dentsim {

// ---- 1. the finish lines -----------------------------------------------------------------------------

struct CrownBand {
  double lo, hi;  // under lo is too little, over hi too much (in the unit its name gives)
};

struct CrownMaterialRow {
  const char* name;      // the task file's crown.material and `task new --material`
  CrownBand occlusal;    // occlusal reduction [mm]
  CrownBand axial;       // axial reduction [mm]
  CrownBand chamfer;     // the finish line's width when it is a chamfer [mm]
  CrownBand shoulder;    // and when it is a shoulder [mm]
};

struct CrownFinishRow {
  const char* name;         // the task file's crown.finish and `task new --finish`
  const char* bur_prefix;   // the burs that cut it, by the stem of their names (assets/tools/tools.json)
  const char* default_bur;  // `task new`'s drill for it
  CrownBand CrownMaterialRow::*width;  // the material's width for this finish line
};

// The bur's end is the finish line's section: the step at the margin is the print of the tip.
inline constexpr CrownFinishRow kCrownFinishTable[] = {
    // A tapered diamond with a rounded end (the ISO 856 shape) leaves a curved step, a chamfer.
    {"chamfer", "chamfer_bur_", "chamfer_bur_016", &CrownMaterialRow::chamfer},
    // A tapered diamond with a flat end (the ISO 847 shape) leaves a flat step square to the wall.
    {"shoulder", "shoulder_bur_", "shoulder_bur_016", &CrownMaterialRow::shoulder},
};

// ---- 2. the materials --------------------------------------------------------------------------------

// Sources: Goodacre CJ, Campagni WV, Aquilino SA, "Tooth preparations for complete crowns: an art
// form based on scientific principles", J Prosthet Dent 2001;85:363-376 (a review of the
// preparation's figures); Shillingburg HT et al., Fundamentals of Fixed Prosthodontics (its
// chapters on the all-ceramic, metal-ceramic and full veneer metal crown preparations).
inline constexpr CrownMaterialRow kCrownMaterialTable[] = {
    // Ceramic alone must be thick enough not to fracture: the figures issue 43 starts from, for
    // either finish (a rounded chamfer or a shoulder, never a knife edge).
    {"all-ceramic", {1.5, 2.0}, {1.0, 1.5}, {0.8, 1.5}, {0.8, 1.5}},
    // A metal coping under porcelain needs room for both on the axial walls; a porcelain margin
    // sits on a shoulder as wide as the all-ceramic one, while a chamfer carries a thin metal collar.
    {"metal-ceramic", {1.5, 2.0}, {1.2, 1.5}, {0.5, 1.0}, {1.0, 1.5}},
    // Cast metal is strong when thin: less off the occlusal surface and the walls, and a narrow chamfer.
    // A shoulder is unusual under a metal crown; it is allowed, a little wider than the chamfer.
    {"metal", {1.0, 1.5}, {0.5, 1.0}, {0.5, 0.8}, {0.8, 1.2}},
};

// ---- 3. what every material shares -------------------------------------------------------------------

// Total occlusal convergence, the angle between opposing axial walls [deg]: 10 to 20 recommended
// (Goodacre 2001); 4 to 10 as some schools teach, and up to 30 still judged acceptable, are near.
inline constexpr CrownBand kCrownTocDeg = {10.0, 20.0};
inline constexpr CrownBand kCrownTocNearDeg = {4.0, 30.0};
// The occlusocervical height: at least 4 mm on a molar, 3 mm on other teeth, and at least 0.4 of the
// preparation's width (Goodacre 2001).
inline constexpr double kCrownMinHeightMolarMm = 4.0;
inline constexpr double kCrownMinHeightOtherMm = 3.0;
inline constexpr double kCrownMinHeightWidthRatio = 0.4;
// The margin's height over the CEJ [mm]: at the CEJ or up to 1 mm above it, where the gingiva leaves
// it clean (supragingival margins where they can be, as the review cited above prefers). dentsim's
// choice of band; a teacher who wants a subgingival margin gives a negative lo.
inline constexpr CrownBand kCrownMarginAboveCejMm = {0.0, 1.0};
// An undercut is a fail criterion of its own (issue 43). Up to this shadow [mm^2] is the voxels'
// noise at a wall's foot; beyond it the total is capped [points of 100]. dentsim's choices.
inline constexpr double kCrownUndercutToleranceMm2 = 0.5;
inline constexpr double kCrownUndercutCap = 50.0;

// ---- 4. look-ups and lists ---------------------------------------------------------------------------

inline const CrownFinishRow* findCrownFinish(const std::string& name) {
  for (const CrownFinishRow& row : kCrownFinishTable)
    if (name == row.name) return &row;
  return nullptr;
}

inline const CrownMaterialRow* findCrownMaterial(const std::string& name) {
  for (const CrownMaterialRow& row : kCrownMaterialTable)
    if (name == row.name) return &row;
  return nullptr;
}

// A finish's bur: its name starts with the finish's prefix ("chamfer_bur_016" cuts a chamfer).
inline bool cutsCrownFinish(const CrownFinishRow& finish, const std::string& bur) {
  return bur.rfind(finish.bur_prefix, 0) == 0;
}

// The finish a bur cuts, by its name, or nullptr for a bur that cuts neither.
inline const CrownFinishRow* crownFinishOfBur(const std::string& bur) {
  for (const CrownFinishRow& row : kCrownFinishTable)
    if (cutsCrownFinish(row, bur)) return &row;
  return nullptr;
}

namespace crown_targets_internal {

// The table's names joined like taskKindNameList: ", " and " or " give "chamfer or shoulder".
template <typename Row, size_t N>
std::string nameList(const Row (&rows)[N], const char* separator, const char* last_separator) {
  std::string out;
  for (size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? last_separator : separator;
    out += rows[i].name;
  }
  return out;
}

constexpr bool bandIsOrdered(CrownBand b) { return b.lo > 0 && b.lo < b.hi; }

constexpr bool materialBandsAreOrdered() {
  for (const CrownMaterialRow& row : kCrownMaterialTable)
    if (!bandIsOrdered(row.occlusal) || !bandIsOrdered(row.axial) || !bandIsOrdered(row.chamfer) ||
        !bandIsOrdered(row.shoulder))
      return false;
  return true;
}

}  // namespace crown_targets_internal

// "chamfer or shoulder" with (", ", " or "); (", ", ", ") for "is not one of" messages.
inline std::string crownFinishNameList(const char* separator, const char* last_separator) {
  return crown_targets_internal::nameList(kCrownFinishTable, separator, last_separator);
}
// "all-ceramic, metal-ceramic or metal" with (", ", " or ").
inline std::string crownMaterialNameList(const char* separator, const char* last_separator) {
  return crown_targets_internal::nameList(kCrownMaterialTable, separator, last_separator);
}

// Every target of a crown of `material` with the `finish` line, on a molar (min_height_mm 4; a
// caller that knows the tooth is not a molar sets kCrownMinHeightOtherMm).
inline CrownTask crownTargets(const CrownFinishRow& finish, const CrownMaterialRow& material) {
  CrownTask c;
  c.finish = finish.name;
  c.material = material.name;
  c.occlusal_lo_mm = material.occlusal.lo;
  c.occlusal_hi_mm = material.occlusal.hi;
  c.axial_lo_mm = material.axial.lo;
  c.axial_hi_mm = material.axial.hi;
  const CrownBand margin = material.*finish.width;
  c.margin_lo_mm = margin.lo;
  c.margin_hi_mm = margin.hi;
  c.toc_lo_deg = kCrownTocDeg.lo;
  c.toc_hi_deg = kCrownTocDeg.hi;
  c.toc_near_lo_deg = kCrownTocNearDeg.lo;
  c.toc_near_hi_deg = kCrownTocNearDeg.hi;
  c.min_height_mm = kCrownMinHeightMolarMm;
  c.min_height_width_ratio = kCrownMinHeightWidthRatio;
  c.margin_above_cej_lo_mm = kCrownMarginAboveCejMm.lo;
  c.margin_above_cej_hi_mm = kCrownMarginAboveCejMm.hi;
  c.undercut_tolerance_mm2 = kCrownUndercutToleranceMm2;
  c.undercut_cap = kCrownUndercutCap;
  return c;
}

// The same by name; an unknown name is an error listing the valid ones.
inline Result<CrownTask> crownTargets(const std::string& finish, const std::string& material) {
  const CrownFinishRow* f = findCrownFinish(finish);
  if (!f) return Error{"finish \"" + finish + "\" is not " + crownFinishNameList(", ", " or ")};
  const CrownMaterialRow* m = findCrownMaterial(material);
  if (!m) return Error{"material \"" + material + "\" is not " + crownMaterialNameList(", ", " or ")};
  return crownTargets(*f, *m);
}

static_assert(crown_targets_internal::materialBandsAreOrdered(), "each band is 0 < lo < hi");
static_assert(crown_targets_internal::bandIsOrdered(kCrownTocDeg) && kCrownTocNearDeg.lo <= kCrownTocDeg.lo &&
                  kCrownTocNearDeg.hi >= kCrownTocDeg.hi,
              "the near convergence holds the recommended one");
static_assert(std::string_view(kCrownFinishTable[0].default_bur) == taskKindRow(TaskKind::Crown).default_bur,
              "the crown kind's bur is its first finish's");

}  // namespace dentsim
