// Scores 0..100 of a student's cut: caries removal (the paper's Table 4) and cavity preparation (Table 5), corrected, and their JSON report.
//
// docs/SCORING.md states each formula, the paper's form, and the rules this adds (an attempt that
// removed nothing earns nothing; no contact samples, no force points).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/session_stats.h"
#include "eval/task.h"
#include "eval/tooth_diff.h"

namespace dentsim {

// Caries removal: removal 0..50, time 0..25, force 0..25 [points].
struct CariesScore {
  double removal = 0.0;               // 50 x removed caries / initial caries
  double time = 0.0;                  // 25 x (failure - elapsed) / (failure - target), clamped; 0 if no caries removed
  double force = 0.0;                 // 25 x (contact - over) / contact, clamped; 0 without contact samples
  double total = 0.0;                 // removal + time + force, 0..100
  double removed_fraction = 0.0;      // removed caries / initial caries; 0 when the tooth has none
  double caries_initial_mm3 = 0.0;
  double caries_removed_mm3 = 0.0;
  double caries_remaining_mm3 = 0.0;
  double enamel_removed_mm3 = 0.0;    // healthy tissue removed [mm^3]
  double dentin_removed_mm3 = 0.0;
  double pulp_removed_mm3 = 0.0;
  bool pulp_exposed = false;
  uint64_t exposed_pulp_voxels = 0;
};

// Cavity preparation: four components 0..25 each [points].
struct CavityScore {
  double undercut = 0.0;              // 25 - undercut x coef x 100 / ideal, clamped
  double overcut = 0.0;               // 25 - overcut x coef x 100 / ideal, clamped (near + gross)
  double parallel = 0.0;              // 25 - parallel_over x coef, clamped
  double time = 0.0;                  // 25 - max(0, elapsed - target) x coef / 60, clamped
  double total = 0.0;                 // the sum, 0..100
  bool nothing_removed = false;       // the attempt removed no tissue: every component is 0
  double ideal_mm3 = 0.0;             // the ideal cavity's volume
  double removed_mm3 = 0.0;
  double undercut_mm3 = 0.0;
  double overcut_mm3 = 0.0;
  double overcut_near_mm3 = 0.0;      // within leeway_mm of the ideal cavity (reported, not scored apart)
  double overcut_gross_mm3 = 0.0;
  double undercut_percent = 0.0;      // of the ideal volume
  double overcut_percent = 0.0;
  bool pulp_exposed = false;
  uint64_t exposed_pulp_voxels = 0;
};

// Clamps v to [lo, hi].
double clampScore(double v, double lo, double hi);

CariesScore scoreCariesRemoval(const ToothDiff& diff, const SessionStats& stats, const Task& task);
// Errors when the diff has no ideal or the ideal cavity is empty (nothing to compare with).
Result<CavityScore> scoreCavityPreparation(const ToothDiff& diff, const SessionStats& stats, const Task& task);

// The files a score came from, as the caller names them (empty: not given).
struct ScoreInputs {
  std::string task;
  std::string initial;
  std::string final_;
  std::string ideal;
  std::string session;
};

// The "dentsim-score" report (version 1): task, inputs, each component with its formula inputs, the
// total, volumes per tissue [mm^3], session statistics. docs/SCORING.md lists the fields.
nlohmann::ordered_json scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
                                       const SessionStats& stats, const CariesScore& score);
nlohmann::ordered_json scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
                                       const SessionStats& stats, const CavityScore& score);

}  // namespace dentsim
