// The professional's ideal of a task: recorded from a session (`dentsim task set-ideal`, the simulator's "Record as ideal") and checked against the tooth it was recorded on.
//
// A task's ideal is only worth its identity: scored against a tooth it was not recorded on, or a
// file that changed since, it would grade every student wrongly without a word. So setTaskIdeal
// stores three hashes with it, and checkIdealIdentity names whichever no longer matches.
#pragma once

#include <string>

#include "core/result.h"
#include "eval/task.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct IdealRecord {
  std::string task_file;     // the task file rewritten
  std::string session_file;  // the session's copy beside it, "<task stem>.ideal.dses"
  std::string final_file;    // the final tooth beside it, "<task stem>.ideal.dvol"
  IdealSpec spec;            // what the task's "ideal" now says (paths relative to the task file)
};

// Makes the recorded session the task's ideal. The session must start on the task's own tooth
// (its hash is the one the task's tooth has); `final_tooth_path` is the session's final tooth (its
// hash must be the one the session's end record names), or empty to replay the session for it.
// Copies the session and the final tooth beside the task file and rewrites the task's "ideal" as
// kind "session" with both paths and the three hashes, keeping every other key as written. The
// task file must be version 2. Every error is one line naming the file at fault.
Result<IdealRecord> setTaskIdeal(const std::string& task_path, const std::string& session_path,
                                 const std::string& final_tooth_path);

// Checks what the ideal's recorded identity says against the tooth being scored (`initial`) and
// the ideal's files: the tooth it was recorded on, the session file, the final tooth. Passes when
// nothing was recorded. `where` starts the message ("task class1_cavity: ideal").
Status checkIdealIdentity(const IdealSpec& ideal, const ToothVolume& initial, const std::string& where);

}  // namespace dentsim
