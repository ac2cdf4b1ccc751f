// One student's own attempts, read back from the outbox of learning-record statements on this PC: per task, how many, the best, whether passed, and the last few with their parts.
//
// The outbox (io/xapi_outbox.h) keeps every statement recorded here, whoever the student was.
// A statement is this student's when its actor's account name is the student's id, and it is an
// attempt at a task when its object's id is that task's activity IRI (eval/learning_record.h's
// taskActivityIri, so the course id and the activity base count too: the same task name in two
// courses is two tasks). Statements without a score (launched, attempted) are no attempts. A line
// that is not a statement costs only itself, with a warning, as in the class report; a missing
// outbox is no error (the student has no attempts yet). The simulator's task picker and Score page
// show what this reads (docs/SIMULATOR.md, "A student's start").
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "eval/attempt_reader.h"

namespace dentsim {

// The most attempts the Score page compares this one with.
inline constexpr size_t kRecentAttempts = 3;

// One student's attempts at one task.
struct TaskRecord {
  int attempts = 0;                    // scored attempts at the task
  std::optional<double> best;          // the best total [points of 100]; none without attempts
  std::vector<ClassAttempt> recent;    // the last kRecentAttempts (or fewer), oldest first
};

// Every attempt of one student in one outbox, by the task's activity IRI, each list oldest first
// (by the statement's timestamp, then the outbox's order).
struct StudentRecords {
  std::string student;                                          // the account name read for
  std::map<std::string, std::vector<ClassAttempt>> by_activity;  // activity IRI -> attempts
  std::vector<std::string> warnings;                            // one line per outbox line left out
};

// Reads `outbox` for `student` (an account name; empty: nobody, so no attempts). Errors: the file
// exists but cannot be read, or is larger than the input limit (one line naming it).
Result<StudentRecords> readStudentRecords(const std::string& outbox, const std::string& student);
// The same from an outbox's text (for tests); `path` names it in warnings.
StudentRecords parseStudentRecords(const std::string& text, const std::string& path, const std::string& student);

// The record of one task: its activity IRI's attempts counted, the best taken, the last few kept.
TaskRecord taskRecord(const StudentRecords& records, const std::string& activity_iri);

// Whether a task counts as passed: with a pass mark, the best total reaches it (the mark the task
// has now, so a teacher who raises it sees who still passes); without one, a task is never passed,
// only tried (a statement's verb is then "completed", eval/learning_record.h).
bool taskPassed(const TaskRecord& record, const std::optional<double>& pass_mark);

// ---- the student's name, kept for the next run ----------------------------------------------------------

// Keeps the name a student typed at the simulator's first-run prompt as the "student" of the
// learning-records config file at `config_path` (io/learning_config.h), so that every later run on
// this PC, and this run's learning records, are that student's. The file's other keys stay as
// they were; a missing file (and its folder) is made, readable by its owner only, as a config that
// may later hold the LRS's password should be. Written atomically. Errors (one line, naming the
// file): a name studentNameProblem refuses, a file that is not a JSON object, one that cannot be written.
Status keepStudentName(const std::string& config_path, const std::string& student);

}  // namespace dentsim
