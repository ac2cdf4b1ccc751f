// The score report's keys that its readers use, typed: what the learning record, the class report and the benchmarks take from a score.json, read and written in this one place.
//
// The report itself (eval/scores.h, scoreReportJson) holds far more: every part's formula and the
// values it used, the zones, the volumes in fill units. Readers want a few of those, and reading
// them by hand in each reader let each one drift from the writer. A ScoreReportSummary is read from
// a whole report (fromJson) and written back as a report cut down to these keys at the same paths
// (toJson), so that anything reading a report reads the cut-down one the same way.
//
// Required: "format" ("dentsim-score"), "task"."name" and "total" in [0, 100]. Every other key may be
// missing (an older report, a part not scored, the adjacent part of a tooth without neighbours) and
// is then none here; the few whose wrong type would make a reader wrong (pulp_exposed, guided,
// student, timestamp, statement_id) are errors when
// present and of the wrong type. Numbers that are not numbers elsewhere are left out, as a later
// version's change of a part must not make a class's reports unreadable.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "volume/tissue_table.h"

namespace dentsim {

// One part of a score as the report lists it: a component earned ("components") or a deduction
// taken off ("deductions").
struct ScoreReportPart {
  std::string name;                    // the report's key: "removal", "undercut", "time", "healthy", "pulp_exposure", ...
  bool deduction = false;              // listed under "deductions"
  bool has_points = false;             // the report gives "points": a number, or null for a part not scored
  std::optional<double> points;        // earned, or taken off [points]; none: not scored, or no "points"
  std::optional<double> max;           // a component's most [points]
  // A part earned in proportion to the work done: its value by the task's table before the share
  // scaled it [points], the measure that names what was done wrong in what was cut.
  std::optional<double> table_points;
  std::optional<double> earned_share;  // earned in proportion to the work done: the share that counted, [0, 1]
  std::optional<double> cap;           // a cap: the total is held to this [points of total_max]
  std::optional<bool> applied;         // a cap: whether it held the total
  bool operator==(const ScoreReportPart&) const = default;
};

// The session's statistics the readers use; the report's "session".
struct ScoreReportSession {
  std::optional<double> elapsed_s;          // how long the attempt took [s]
  std::optional<uint64_t> contact_samples;  // haptic steps with the bur on the tooth
  std::optional<uint64_t> force_over;       // of those, the steps over the task's force limit
  std::optional<double> max_force_n;        // [N]
  std::optional<double> mean_force_n;       // over the contact samples [N]
  bool operator==(const ScoreReportSession&) const = default;
};

// The surface agreement's whole-cavity shares; the report's "surface_agreement" less its walls.
struct ScoreReportAgreement {
  double band_mm = 0.0;                     // the tolerance band, plus or minus [mm]
  std::optional<uint64_t> samples;          // points measured on the ideal cavity's surface
  double within_percent = 0.0;              // the ideal surface's share matched within the band [%]
  std::optional<double> beyond_percent;     // cut beyond the band [%]
  std::optional<double> short_percent;      // left short of the band [%]
  bool operator==(const ScoreReportAgreement&) const = default;
};

// The guide whose spring pulled the drill; the report's "guided", present only for a guided attempt.
struct ScoreReportGuide {
  std::string source;                       // the guide's file
  std::optional<std::string> source_hash;   // XXH3 of it (hex)
  std::optional<double> stiffness_n_per_mm; // the spring [N/mm]
  std::optional<double> max_force_n;        // the spring's most [N]
  bool operator==(const ScoreReportGuide&) const = default;
};

struct ScoreReportSummary {
  int version = 2;                          // the report's "version"
  std::string task_name;                    // "task"."name": "caries_removal", "class2_cavity", ...; required
  std::string task_title;                   // "task"."title"; empty when the report has none
  std::string task_kind;                    // "task"."kind": "caries", "cavity", "access", "crown"; empty when none
  double total = 0.0;                       // the headline score [points of 100], [0, 100]; required
  std::optional<double> total_max;          // what the parts scored can reach: 100, or less without a session
  std::optional<double> paper_total;        // "paper_total": the parts summed by the paper's formulas, before shares, caps and clamps [points]
  std::vector<ScoreReportPart> parts;       // components, then deductions, in the report's order
  std::optional<double> completion_share;   // "completion"."share": the share of the work done that earned parts scale by, [0, 1]
  // Removed anywhere, by kScoredTissues' order (enamel, dentin, pulp, caries, neighbour): "volumes"."<tissue>"."removed_mm3"
  // [mm^3]; a neighbour's only on a tooth that has one.
  std::array<std::optional<double>, kTissueCount> removed_mm3{};
  std::optional<double> overcut_mm3;        // "volumes"."all"."overcut_mm3": cut beyond the ideal cavity [mm^3]; an ideal's report only
  std::optional<double> undercut_mm3;       // "volumes"."all"."undercut_mm3": the ideal cavity left standing [mm^3]; an ideal's report only
  std::optional<double> healthy_outside_zone_mm3;  // "zones"."healthy_outside_zone_mm3": healthy tissue cut outside the allowed zone [mm^3]
  std::optional<double> caries_remaining_mm3;      // a caries removal's caries left [mm^3]
  // "deductions"."adjacent": the adjacent teeth's volume the cut removed [mm^3]; none when the tooth
  // had no neighbour (the report then has no such part) or the report is older than neighbours.
  std::optional<double> adjacent_removed_mm3;
  bool adjacent_damaged = false;            // "deductions"."adjacent"."damaged": removed above the noise floor
  bool pulp_exposed = false;                // the cut reached the pulp (an access cavity's: opened the chamber)
  std::optional<ScoreReportSession> session;      // none: scored without a session
  std::optional<ScoreReportAgreement> agreement;  // cavity and access with an ideal: how the surfaces agree
  std::optional<ScoreReportGuide> guided;         // none: the student's own hand
  std::optional<std::string> statement_id;  // the learning record's statement id (app/learning_cli.h stamps it)
  std::optional<std::string> student;       // who did it, when the report says (dentsim's reports do not)
  std::optional<std::string> timestamp;     // when it ended, ISO 8601, when the report says (dentsim's do not)

  // What counts as cut beyond and short of the target: a cavity measures against its ideal; a caries
  // removal, which has none, counts the healthy tissue cut outside the allowed zone as its over-cut
  // and the caries left standing as its under-cut.
  std::optional<double> overcutOrHealthyOutsideMm3() const { return overcut_mm3 ? overcut_mm3 : healthy_outside_zone_mm3; }
  std::optional<double> undercutOrCariesLeftMm3() const { return undercut_mm3 ? undercut_mm3 : caries_remaining_mm3; }

  // The report cut down to these keys, at their paths and in the report's order.
  nlohmann::ordered_json toJson() const;
  // Reads them from a whole report. The error is one line naming the key: "total: missing or not a
  // number in [0, 100]".
  static Result<ScoreReportSummary> fromJson(const nlohmann::ordered_json& report);

  bool operator==(const ScoreReportSummary&) const = default;
};

}  // namespace dentsim
