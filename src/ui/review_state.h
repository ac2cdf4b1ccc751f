// What the panel shows of the student and of the review after a score: the name at the first run, the review's buttons with why each is off, this attempt beside the last ones (the app fills it; ui/review_panel.h draws it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"

namespace dentsim::ui {

// The student at the simulator. Named by the config or --student, or at the first-run prompt.
struct StudentView {
  std::string id;             // set by the app: the account name the records are for; empty: nobody named
  bool ask = false;           // set by the app: nobody named in a student's start, so the window asks once
  std::string typed;          // the prompt's field
  std::string error;          // set by the app: why the last name was not kept
  std::string where;          // set by the app: where the name is kept (the config file)
};

// One review button: whether it can be pressed and, when not, why (its tooltip).
struct ReviewButton {
  bool available = false;
  std::string why_not;        // shown in the disabled button's tooltip; empty while available
};

// The Score page's review (set by the app after a score): this attempt's replay, the same with the
// professional's ghost beside it, a retry with the guide's spring on, and this attempt's parts
// against the last attempts at the task from the student's records (eval/student_records.h).
struct ReviewView {
  ReviewButton replay;                  // this attempt's recorded session, replayed in the window
  ReviewButton ghost;                   // the same with the task's recorded ideal as the ghost
  ReviewButton guided;                  // a new attempt with the guide pulling toward the ideal
  std::optional<ClassAttempt> now;      // this attempt's total and parts; none: nothing scored yet
  std::vector<ClassAttempt> before;     // the last attempts before this one at this task, oldest first
  std::string records_note;             // why there are no earlier attempts to show; empty: none to say
};

// What the student asked for on the Score page or at the prompt this frame.
struct ReviewActions {
  bool replay = false;                  // the Replay button
  bool replay_ghost = false;            // Replay with the professional's ghost
  bool retry_guided = false;            // Retry with guidance
  std::string name_given;               // the prompt's name, given this frame; empty: none
};

}  // namespace dentsim::ui
