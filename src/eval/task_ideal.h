// The professional's ideal of a task: recorded from a session (`dentsim task set-ideal`, the simulator's "Record as ideal") and checked against the tooth it was recorded on.
//
// A task's ideal is only worth its identity: scored against a tooth it was not recorded on, or a
// file that changed since, it would grade every student wrongly without a word. So setTaskIdeal
// stores three hashes with it, and checkIdealIdentity names whichever no longer matches.
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "eval/task.h"
#include "io/session_file.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The rule that sets a task's times from its professional's recorded attempt (docs/SCORING.md,
// section 10). A student is given a quarter more than the professional took, and loses every time
// point at three times it: a professional who took 8 s sets target_s 10 s, and a cavity's 25 time
// points are gone at 24 s. The time is the whole session, not only the cutting, because a score's
// time part measures the whole session (eval/session_stats.h's elapsed_s).
inline constexpr double kTargetFactor = 1.25;   // target_s = this x the professional's elapsed time
inline constexpr double kFailureFactor = 3.0;   // no time points left at this x it
// The task with target_s = kTargetFactor x professional_elapsed_s [s], and: a caries task's
// failure_s = kFailureFactor x it; a cavity or access task's cavity.time_coefficient such that its
// 25 points (section 5) are gone at kFailureFactor x it, 25 x 60 / ((3 - 1.25) x elapsed) points a
// minute. professional_elapsed_s > 0.
Task timedFromProfessional(Task task, double professional_elapsed_s);

// The professional's bur axis while cutting: the mean of the drill's bur axis (the grip's +z, as
// burTiltDeg measures it) over the steps in contact with the tooth with the pedal down, normalized.
// None when no step cut, or the axes cancel out.
std::optional<Vec3> meanCuttingBurAxis(const SessionRecording& session);

// What set-ideal read of the professional's session.
struct ProfessionalFigures {
  double elapsed_s = 0.0;              // the whole session [s] (sessionStats' elapsed_s)
  double contact_s = 0.0;              // the drill in contact with the tooth: contact samples / rate [s]
  std::string drill_tool;              // the professional's bur (the session header's)
  std::optional<Vec3> bur_axis;        // meanCuttingBurAxis; none: no step cut
  double bur_axis_from_crown_deg = 0;  // the angle between it and the tooth's crown axis [deg]
};

struct IdealRecord {
  std::string task_file;     // the task file rewritten
  std::string session_file;  // the session's copy beside it, "<task stem>.ideal.dses"
  std::string final_file;    // the final tooth beside it, "<task stem>.ideal.dvol"
  IdealSpec spec;            // what the task's "ideal" now says (paths relative to the task file)
  ProfessionalFigures professional;
  Task task;                 // the task as now written (its tooth path as the file says it)
  bool axis_set = false;     // insertion_axis is now professional.bur_axis (the task's from_ideal listed it)
  bool times_set = false;    // the times are now timedFromProfessional's (from_ideal listed target_s)
  // From_ideal listed insertion_axis but it was kept: why (no cutting step; or checkInsertionAxis's
  // line, the professional's axis not being valid for the task's kind). Empty otherwise.
  std::string axis_kept_reason;
};

// Makes the recorded session the task's ideal. The session must start on the task's own tooth
// (its hash is the one the task's tooth has); `final_tooth_path` is the session's final tooth (its
// hash must be the one the session's end record names), or empty to replay the session for it.
// Copies the session and the final tooth beside the task file and rewrites the task's "ideal" as
// kind "session" with both paths and the three hashes. The keys the task's "from_ideal" lists are
// set from the session too: insertion_axis to meanCuttingBurAxis (kept when none, or when it is not
// valid for the task's kind: eval/task_axis.h), target_s and the rest of the times by
// timedFromProfessional. The list stays, so a professional recorded again sets them again. Every
// other key is kept as written. The task file must be version 2. Every error is one line naming
// the file at fault.
Result<IdealRecord> setTaskIdeal(const std::string& task_path, const std::string& session_path,
                                 const std::string& final_tooth_path);

// Checks what the ideal's recorded identity says against the tooth being scored (`initial`) and
// the ideal's files: the tooth it was recorded on, the session file, the final tooth. Passes when
// nothing was recorded. `where` starts the message ("task class1_cavity: ideal").
Status checkIdealIdentity(const IdealSpec& ideal, const ToothVolume& initial, const std::string& where);

}  // namespace dentsim
