// A task proves its own score: scripted attempts derived from its professional's session (a second careful hand and one per fault) are drilled, scored like a student's, and checked.
//
// `dentsim task validate` and `dentsim bench scores` both run this, so the attempts a teacher's
// task is checked with are the benchmark's. The professional's session is the task's ideal session;
// a task whose ideal is a built-in path (or a caries task without an ideal) has its built-in
// professional's path drilled and recorded first, and the attempts are derived from that recording.
// A task whose ideal is only a volume file has no motion to derive from: an error says to set one.
//
// The attempts are the kind's: kAttempts (sim/novice_paths.h) at a caries removal, a cavity or an
// access, kCrownAttempts at a crown preparation (docs/SCORING.md, "Crown preparation: scripted attempts").
//
// The checks (docs/SCORING.md section 13), each failure one line naming the attempt and the part:
//   - the expert scores at least expert_floor (85);
//   - every fault loses at least min_gap (20) points against the expert; at a crown crown_min_gap
//     (10): a crown's criterion is worth 10 to 20 points, so a fault outside one criterion's range
//     loses 10 to 20 (one near it half that), where a cavity's fault moves parts worth 25 to 50;
//   - every fault loses most in its own part (faultParts): its own parts lose more than any other
//     one part does, measured at each part's own value before the share of the ideal cut scales it;
//   - undercut, token and trench do not pass (the task's pass mark, 70 when it has none).
// A caries removal has no bur-angle part, so `tilted` is not run on one (the report says so).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/score_summary.h"
#include "eval/task.h"
#include "sim/novice_paths.h"
#include "sim/session_attempts.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct ValidationSettings {
  std::vector<Attempt> attempts;  // empty: the kind's list; the expert is always run, first; an attempt
                                  // of the other kinds' list is skipped (the report says so)
  DerivedAttemptSettings derive;  // how far each attempt departs from the professional (the heavy hand's
                                  // press is set from the task's force limit, derivedSettingsFor)
  double expert_floor = 85.0;     // the expert's total must reach this [points of 100]
  double min_gap = 20.0;          // every fault must lose this much against the expert [points]
  double crown_min_gap = 10.0;    // at a crown preparation [points]
  double default_pass_mark = 70.0;  // for a task without a pass mark
  std::string work_dir;           // where the sessions are written (required); each is removed once read back
  std::string picture_dir;        // each attempt's score picture <task>-<attempt>.png; empty: none
  // Set the task's times from the professional recorded here (task_ideal.h's rule), as set-ideal
  // would: for a built-in task drilled at another level than the one its times were set at.
  bool time_from_professional = false;
};

// One attempt, drilled and scored.
struct ValidatedAttempt {
  Attempt attempt = Attempt::Expert;
  double total = 0.0, total_max = 100.0, paper_total = 0.0;
  std::vector<std::pair<std::string, double>> parts;  // the points each part counts; deductions and caps negative
  double elapsed_s = 0.0;                             // the recorded session's length [s]
  double mean_force_n = 0.0, max_force_n = 0.0;       // over the contact samples [N]
  std::optional<double> agreement_percent;            // surface within the band (cavity and access)
  bool pulp_exposed = false;
  std::string final_hash;                             // volumeHash of the cut tooth
  ScoreReportSummary summary;                         // the "dentsim-score" report's keys, as every reader reads them
};

// How one fault compares with the expert.
struct FaultCheck {
  Attempt attempt = Attempt::Expert;
  double gap = 0.0;             // expert's total - this total [points]
  double lost = 0.0;            // points lost against the expert, part by part (gains not counted)
  double lost_in_fault = 0.0;   // of those, in the fault's own parts
  std::string most_lost_part;   // the part that lost most
  double most_lost_elsewhere = 0.0;  // the most any one part outside the fault's own lost [points]
  bool passes = false;          // total >= pass mark
  // "Loses most in its own part": its own parts together lose something, and at least as much as
  // any other single part does, so that the report's largest loss names the fault.
  bool mostInOwnPart() const { return lost_in_fault > 0 && lost_in_fault >= most_lost_elsewhere; }
};

struct TaskValidation {
  Task task;                    // as scored (with its times from the professional when the settings say so)
  bool timed_here = false;      // the times were set from this run's professional
  std::string professional;     // where the professional's session came from
  double professional_s = 0.0;  // its length [s]
  double pass_mark = 70.0;
  double expert_floor = 85.0;   // the checks' figures, as the settings and the kind set them [points]
  double min_gap = 20.0;
  std::vector<ValidatedAttempt> attempts;  // the expert first, then the settings' order
  std::vector<FaultCheck> faults;          // each attempt but the expert
  std::vector<std::string> skipped;        // attempts not run, each with why
  std::vector<std::string> failures;       // one line each: the attempt, the part, what is wrong
  bool valid() const { return failures.empty(); }
};

// The attempts validateTask runs at a task of `kind` by default: kCrownAttempts at a crown, else kAttempts.
std::vector<Attempt> kindAttempts(TaskKind kind);
// The parts an attempt's fault should cost ("overcut", "force", ...): the part names of the report
// (a crown's: eval/crown_score.h's criteria, "adjacent", and "undercut cap" for its cap).
std::vector<std::string> faultParts(TaskKind kind, Attempt attempt);
// How a fault's attempt compares with the expert's, part by part: its own parts are faultParts', and
// on a tooth with neighbours the adjacent-tooth deduction too when the fault cuts beyond where it
// belongs (its own parts hold "overcut" or "healthy").
FaultCheck compareWithExpert(const ValidatedAttempt& expert, const ValidatedAttempt& fault, TaskKind kind, double pass_mark);

// The professional's session of `task` on `tooth` (its starting tooth): the ideal's session, or the
// built-in professional recorded into `work_dir`. `from` is told where it came from.
Result<SessionRecording> professionalSession(const Task& task, const ToothVolume& tooth, const std::string& work_dir,
                                             std::string* from);

// Drills and scores every attempt at `task` on `tooth` and checks them. `progress` is told each
// step as it starts (may be empty). Errors: no professional session to derive from, a failed run.
Result<TaskValidation> validateTask(const Task& task, const ToothVolume& tooth, const ValidationSettings& settings,
                                    const std::function<void(const std::string&)>& progress = {});

// `validation.json`: {"task", "pass_mark", "professional", "attempts": [{"attempt", "total", "parts", ...}],
// "checks": [...], "skipped", "failures", "valid"}.
nlohmann::ordered_json validationJson(const TaskValidation& v);
// The same as a Markdown table, with each check's verdict.
std::string validationMarkdown(const TaskValidation& v);

}  // namespace dentsim
