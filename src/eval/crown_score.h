// The full-crown preparation's score: each examiner's criterion within, near or outside its range from the task, the points it earns, and the report, lines and picture marks.
//
// docs/SCORING.md ("Crown preparation") states every rule. In short: the finish line (findMargin)
// gives the margin height every other measure starts from; seven criteria are graded against the
// task's ranges (Task::crown), within earning their points, near half, outside none; the ones an
// untouched tooth could meet by doing nothing are earned in proportion to the share of the
// preparation done; an undercut beyond the task's tolerance caps the total, as an exposed pulp does;
// the adjacent-tooth deduction is every kind's. The session's time and force are reported, not scored.
// The measures read the teeth at half fill (a voxel at least 16 of 31 full is tooth), as the picture does.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/crown_prep_margin.h"
#include "eval/crown_prep_reduction.h"
#include "eval/crown_prep_taper.h"
#include "eval/crown_prep_undercut.h"
#include "eval/cut_marks.h"
#include "eval/scores.h"
#include "eval/session_stats.h"
#include "eval/task.h"
#include "eval/tooth_diff.h"
#include "volume/brick_volume.h"
#include "volume/loose_fragments.h"

namespace dentsim {

enum class CrownVerdict { Within, Near, Outside };
// "within", "near", "outside".
const char* crownVerdictName(CrownVerdict verdict);

// The criteria in the report's order; kCrownCriteria names them.
enum class CrownCriterionId : int {
  OcclusalReduction = 0,
  AxialReduction,
  Taper,
  Height,
  MarginWidth,
  MarginLine,
  Undercut,
};
inline constexpr int kCrownCriterionCount = 7;

// One criterion as graded.
struct CrownCriterion {
  const char* name = "";            // the report's key: "occlusal_reduction", "taper", ...
  double max = 0.0;                 // its points when within [points of 100]
  bool measured = false;            // false: no figure to grade (no finish line, a measure failed); outside
  CrownVerdict verdict = CrownVerdict::Outside;
  double verdict_points = 0.0;      // max, max / 2 or 0 by the verdict
  // Earned in proportion to the work done: the share that counted, [0, 1]; none for the criteria
  // earned in full (the reductions).
  std::optional<double> share;
  double points = 0.0;              // what counts: verdict_points x share (or verdict_points)
  std::string value;                // the deciding figure in words, "12.4 deg" (empty when not measured)
  std::string band;                 // the range within, short, for a screen: "10-20"
  std::string range;                // the range in words, "10-20 deg (near 4-30)"
  std::string source;               // where the range comes from
  std::string why;                  // not measured: why; otherwise which figure decided
};

// Where a margin sector lies around the tooth, in words: "mesial", "mesiobuccal", "buccal", ...
// (the nearest of the eight directions to the sector's middle; sector 0 starts at mesial and the
// sectors turn toward buccal, as eval/crown_prep_margin.h counts them).
const char* marginSectorDirection(int sector);

struct CrownScore {
  // The measures, each none when it could not be taken (why: *_error).
  MarginLine margin;                       // found_sectors 0: nothing prepared, no finish line
  bool margin_found = false;
  double margin_height_mm = 0.0;           // handed to the other measures: the mean height of the line [mm]
  std::optional<CrownPrepShape> shape;
  std::string shape_error;
  std::optional<CrownPrepReduction> reduction;
  std::string reduction_error;
  std::optional<UndercutMap> undercut;
  std::string undercut_error;
  // The completion: the share of the original's surface samples above the margin (occlusal and
  // axial) whose reduction reached at least half their band's lo (those taken off whole count as
  // reached), and the share the criteria earned in proportion count: min(1, that / 0.8).
  double reached_share = 0.0;
  double completion = 0.0;
  int completion_samples = 0;
  int completion_reached = 0;
  double coverage = 0.0;                   // the finish line's sectors found / kMarginSectors, [0, 1]
  // Pieces of the prepared tooth cut free of it (volume/loose_fragments.h): measured as gone.
  LooseFragments loose;
  double loose_mm3 = 0.0;

  std::array<CrownCriterion, kCrownCriterionCount> criteria{};
  const CrownCriterion& criterion(CrownCriterionId id) const { return criteria[size_t(id)]; }

  AdjacentScore adjacent;
  bool undercut_failed = false;            // the shadow is beyond the task's tolerance
  bool undercut_cap_applied = false;       // and the cap lowered the total
  bool pulp_exposed = false;
  uint64_t exposed_pulp_voxels = 0;
  bool pulp_cap_applied = false;
  double criteria_total = 0.0;             // the criteria's verdict points summed, before shares, deductions and caps
  double total = 0.0;                      // clamp(sum of points - adjacent, 0, 100), capped
  double total_max = 100.0;                // always 100: nothing a crown is graded on needs the session
};

// Scores `final_` as a crown preparation of `initial` under task.crown. diff: compareTeeth's of the
// same teeth (for the adjacent deduction and the pulp). The insertion axis is the task's, mesial
// the initial tooth's frame (frame.tooth.mesial, grid axes). Errors, one line: the teeth on
// different grids, a mesial along the insertion axis.
Result<CrownScore> scoreCrownPreparation(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                                         const ToothDiff& diff);

// The "dentsim-score" report of a crown (the same header, totals, deductions and tail as the other
// kinds; "components" holds the criteria, each with its figures, range, source and verdict).
nlohmann::ordered_json scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
                                       const SessionStats* stats, const CrownScore& score);
// One line per criterion (detail: "taper 12.4 deg (10-20) within"), then the adjacent deduction.
std::vector<ScoreLine> scoreLines(const CrownScore& score);
// One line for the terminal.
std::string scoreSummary(const CrownScore& score, const ScoreInputs& inputs);

// The task's reduction bands as eval/crown_prep_reduction.h takes them.
ReductionBands crownReductionBands(const CrownTask& crown);

// The reduction map's paint (eval/score_image.h's codes), the one the score picture and the
// window's map share: each prepared surface voxel a gauge reading met, kPaintGreen within its band,
// kPaintBlue under, kPaintRed over; a voxel met by readings of different bands shows under, then
// within, then over. With `prepared` (the prepared tooth's voxels), each painted voxel also lends
// its colour to its unpainted tooth neighbours (26): a picture's ray stops at the first voxel at
// least half full, under a thin outer voxel the one behind it.
CutMarks reductionPaint(const CrownPrepReduction& reduction, const BrickVolume* prepared = nullptr);

// The score picture's paint: the reduction map (reductionPaint), the finish line yellow and the
// undercut magenta over it.
CutMarks crownPaint(const CrownScore& score, const BrickVolume* prepared = nullptr);

}  // namespace dentsim
