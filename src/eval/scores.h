// Scores 0..100 of a student's cut: caries removal (the paper's Table 4) and cavity preparation (Table 5), corrected and extended to count healthy tissue, force and pulp exposure, and their JSON report.
//
// docs/SCORING.md states each formula, the paper's form, and the rules this adds: healthy tissue cut
// outside the allowed zone costs points, an exposed pulp caps the total, a part whose input is
// missing is "not scored" (never free points), and an attempt that misses its target earns nothing.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/session_stats.h"
#include "eval/task.h"
#include "eval/tooth_diff.h"
#include "volume/tissue_table.h"

namespace dentsim {

// Damage to an adjacent tooth, the same deduction in every kind (docs/SCORING.md, "Adjacent teeth"):
// the neighbour voxels the cut removed, anywhere. Removal at or under the noise floor (the task's
// adjacent.noise_voxels of fill) is the bur grazing a contact and costs nothing; above it the
// deduction is min_points + coefficient x removed_mm3 [points].
struct AdjacentScore {
  bool has_neighbour = false;       // the initial tooth holds neighbour voxels; without, the report leaves the part out
  double initial_mm3 = 0.0;         // the neighbours' volume at the start [mm^3]
  double removed_mm3 = 0.0;         // neighbour removed, anywhere [mm^3]
  double noise_floor_mm3 = 0.0;     // noise_voxels voxels' volume [mm^3]
  bool damaged = false;             // removed above the noise floor
  double deduction = 0.0;           // damaged: min_points + coefficient x removed_mm3; else 0 [points]
};

// Caries removal: the paper's removal 0..50, time 0..25 and force 0..25, less the healthy tissue
// cut outside the allowed zone, capped when the pulp is exposed [points].
struct CariesScore {
  double removal = 0.0;                 // 50 x removed caries / initial caries
  std::optional<double> time;           // 25 x (failure - elapsed) / (failure - target), clamped; 0 if no caries removed; none without a session
  std::optional<double> force;          // 25 x (contact - over) / contact, clamped; 0 without contact samples; none without a session
  double paper_total = 0.0;             // Table 4's total over the parts scored: removal + time + force
  // Time and force are earned in proportion to the caries removed (docs/SCORING.md section 4):
  // the total counts removal + removed_fraction x (time + force). The parts above are Table 4's.
  double earned_time = 0.0;             // removed_fraction x time [points]
  double earned_force = 0.0;            // removed_fraction x force [points]
  double healthy_deduction = 0.0;       // healthy_coefficient x 100 x healthy outside / caries initial [points]
  AdjacentScore adjacent;               // an adjacent tooth cut: its own deduction
  bool pulp_cap_applied = false;        // the pulp is exposed and the cap lowered the total
  double total = 0.0;                   // the headline: clamp(removal + earned time and force - healthy_deduction - adjacent, 0, total_max), capped
  double total_max = 100.0;             // what the parts scored can reach: 100, or 50 without a session
  double removed_fraction = 0.0;        // removed caries / initial caries (with an ideal: of the caries the ideal removed); 0 when none
  bool against_ideal = false;           // the removal is measured against the caries a professional's ideal removed
  double caries_initial_mm3 = 0.0;
  double caries_removed_mm3 = 0.0;
  double caries_remaining_mm3 = 0.0;
  // Each tissue removed anywhere, by tissue table row [mm^3]; the report lists the healthy ones
  // (isHealthyTissue), since the caries removed has its own fields above.
  std::array<double, kTissueCount> removed_mm3{};
  double removedMm3(Material m) const { return removed_mm3[size_t(tissueIndex(m))]; }  // m a tissue of the table
  double healthy_outside_mm3 = 0.0;     // enamel, dentin and pulp removed in the container [mm^3]
  double healthy_outside_percent = 0.0; // of the initial caries volume
  bool pulp_exposed = false;
  uint64_t exposed_pulp_voxels = 0;
};

// Cavity preparation: the paper's four parts 0..25 each, the over-cut, parallel and time parts earned
// in proportion to the share of the ideal cavity cut, less the force errors, capped when the pulp is
// exposed [points]. An access cavity scores the same parts, but its cap is the other way round: a
// pulp chamber left closed caps it, an opened one is the exercise.
struct CavityScore {
  double undercut = 0.0;                // 25 - undercut x coef x 100 / ideal, clamped
  double overcut = 0.0;                 // 25 - (gross + near_weight x near) x coef x 100 / ideal, clamped
  std::optional<double> parallel;       // 25 - parallel_over x coef, clamped; none without a session
  std::optional<double> time;           // 25 - max(0, elapsed - target) x coef / 60, clamped; none without a session
  double paper_total = 0.0;             // Table 5's total over the parts scored: the four parts as they stand
  double completion = 0.0;              // the share of the ideal cavity cut: target removed / ideal, [0, 1]
  double earned_overcut = 0.0;          // completion x overcut [points]
  std::optional<double> earned_parallel;// completion x parallel; none without a session
  std::optional<double> earned_time;    // completion x time; none without a session
  std::optional<double> force_deduction;  // force_coefficient x 100 x force_over / contact; none without a session
  AdjacentScore adjacent;               // an adjacent tooth cut: its own deduction
  bool pulp_cap_applied = false;
  bool access = false;                  // the task's kind must open the pulp chamber (PulpRule::MustOpen: an access cavity)
  bool unopened_cap_applied = false;    // access: the pulp chamber was not opened and the cap lowered the total
  double total = 0.0;                   // clamp(undercut + the earned parts - force_deduction - adjacent, 0, total_max), capped
  double total_max = 100.0;             // 100, or 50 without a session
  bool nothing_removed = false;         // the attempt removed no tissue
  bool ideal_missed = false;            // it removed nothing of the ideal cavity: completion 0, every part earned is 0
  double ideal_mm3 = 0.0;               // the ideal cavity's volume
  double removed_mm3 = 0.0;
  double undercut_mm3 = 0.0;
  double overcut_mm3 = 0.0;
  double overcut_counted_mm3 = 0.0;     // what the over-cut part counts: gross + near_weight x near
  double overcut_near_mm3 = 0.0;        // in the leeway around the ideal cavity (reported, not scored apart)
  double overcut_gross_mm3 = 0.0;       // in the container
  double undercut_percent = 0.0;        // of the ideal volume
  double overcut_percent = 0.0;
  bool pulp_exposed = false;
  uint64_t exposed_pulp_voxels = 0;
};

// Clamps v to [lo, hi].
double clampScore(double v, double lo, double hi);

// The adjacent-tooth deduction of a diff under the task's adjacent terms; both scores below hold it.
AdjacentScore scoreAdjacent(const ToothDiff& diff, const Task& task);

// `stats` null: there is no session, and the parts that need one are not scored.
CariesScore scoreCariesRemoval(const ToothDiff& diff, const SessionStats* stats, const Task& task);
// Also scores an access cavity (task.kind Access). Errors when the diff has no ideal or the ideal
// cavity is empty (nothing to compare with).
Result<CavityScore> scoreCavityPreparation(const ToothDiff& diff, const SessionStats* stats, const Task& task);

// Why a score may be wrong although it computes: the task's insertion axis points away from the
// tooth's crown, the ideal cavity lies mostly outside the crown half, or the cut does not overlap
// the ideal at all. Each line names the task and the tooth (`tooth_name`).
std::vector<std::string> scoreWarnings(const Task& task, const ToothDiff& diff, const std::string& tooth_name);

// The files a score came from, as the caller names them (empty: not given).
struct ScoreInputs {
  std::string task;
  std::string initial;
  std::string final_;
  std::optional<IdealSpec> ideal;   // the ideal used, whatever its source
  std::string ideal_from;           // where it was named: "task" or "command line"
  std::string session;
  std::string no_session_reason = "no session was given";  // when session is empty
  std::vector<std::string> warnings;  // scoreWarnings() and the caller's own
};

// The "dentsim-score" report (version 2): task, inputs, each part with its formula inputs (null with
// a reason when not scored), the paper's total, the deductions, the total and what it is out of,
// the zones, warnings, volumes per tissue [mm^3], session statistics. docs/SCORING.md lists the fields.
nlohmann::ordered_json scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
                                       const SessionStats* stats, const CariesScore& score);
nlohmann::ordered_json scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
                                       const SessionStats* stats, const CavityScore& score);

// The report's shared pieces, for a kind scored in a file of its own (eval/crown_score.h), so that
// its report keeps the same shape: the header (format, version, task, inputs); the totals with the
// parts not scored; the adjacent-tooth deduction and the pulp-exposure cap as "deductions" hold
// them; the zones, the volumes and the session block.
nlohmann::ordered_json scoreReportHeader(const Task& task, const ScoreInputs& inputs);
void scoreReportTotals(nlohmann::ordered_json& report, double total, double total_max, double paper_total,
                       const std::vector<std::string>& not_scored, const ScoreInputs& inputs);
nlohmann::ordered_json adjacentDeductionJson(const Task& task, const AdjacentScore& adjacent);
// The cap an exposed pulp puts on a total out of total_max [points]: the task's cap is out of 100.
double pulpExposureCap(const Task& task, double total_max);
nlohmann::ordered_json pulpExposureCapJson(const Task& task, bool exposed, bool applied, double total_max);
nlohmann::ordered_json scoreZonesJson(const ToothDiff& diff);
nlohmann::ordered_json scoreVolumesJson(const ToothDiff& diff);
nlohmann::ordered_json scoreSessionJson(const SessionStats* stats, const ScoreInputs& inputs);

// A score's parts and deductions in the report's order, for a screen to show without reading JSON.
struct ScoreLine {
  std::string name;               // the report's key: "removal", "time", ...; "healthy", "force", "adjacent"
  std::optional<double> points;   // none: not scored (no session)
  double max = 0.0;               // what a part can reach; 0 for a deduction
  bool deduction = false;         // points are taken off the total
  // A part graded against a range (a crown's criteria): what was measured, the range and the
  // verdict in words, "12.4 deg (10-20) within"; empty for the parts scored by formula.
  std::string detail;
};
std::vector<ScoreLine> scoreLines(const CariesScore& score);
std::vector<ScoreLine> scoreLines(const CavityScore& score);

// One line for the terminal: the total out of its maximum, each part, what was not scored and why.
std::string scoreSummary(const CariesScore& score, const ScoreInputs& inputs);
std::string scoreSummary(const CavityScore& score, const ScoreInputs& inputs);

}  // namespace dentsim
