// The learning records on the command line: the options score, demo and run share, the one function every scored attempt goes through, and sending the outbox to the LRS after the work.
//
// A scored attempt becomes an xAPI statement (eval/learning_record.h) in the outbox
// (io/xapi_outbox.h) when a student is named, by --student or the config file; without one,
// nothing is recorded. One policy for all three commands: a mistake in the options (a bad
// --student, --lrs or config) is an error before any work (checkLearningOptions), and after that
// nothing about the records fails a scored attempt: an outbox that cannot be written or an LRS that
// does not answer is one warning line, the score files stand and the command succeeds. Sending
// (io/outbox_sender.h) happens after the work, never inside the frame loop. docs/LEARNING_RECORDS.md.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/learning_record.h"
#include "eval/task.h"
#include "io/lrs_client.h"

namespace dentsim::app {

struct LearningCliOptions {
  std::string student;  // --student: the account name; empty: the config's
  std::string course;   // --course (--course-id on run): the course id; empty: the config's, else "builtin"
  std::string lrs;      // --lrs: the LRS's xAPI endpoint; empty: the config's, else no sending
  std::string outbox;   // --outbox: the outbox file; empty: the config's, else the default place
  std::string config;   // --config: the config file; empty: $DENTSIM_CONFIG or the default place
};

// Adds --student, --course (or `course_flag` where the command's --course means something else),
// --lrs, --outbox and --config.
void addLearningOptions(CLI::App* cmd, LearningCliOptions& o, const std::string& course_flag = "--course");

// Builds a scored attempt's statement and adds it to the outbox (once per id); commands go through
// recordAttemptOrWarn, which joins this and stampStatementId under the one policy.
// `session_file` is the session the score used (empty: none), `final_file` the final tooth file
// (used for the attempt's identity when there is no session). Does nothing without a student.
// Errors: a malformed config (file and key named), an outbox that cannot be written.
Status recordAttempt(const LearningCliOptions& o, const Task& task, const nlohmann::ordered_json& report,
                     const std::string& session_file, const std::string& final_file);

// Names the attempt's statement in its score report before the report is written: the report gains
// "statement_id", the id recordAttempt gives the statement (eval/learning_record.h's statementId), so
// that a class report holding both counts the attempt once. Does nothing without a student. Same
// inputs and errors as recordAttempt; call it with the same ones.
Status stampStatementId(const LearningCliOptions& o, const Task& task, nlohmann::ordered_json& report,
                        const std::string& session_file, const std::string& final_file);

// Checks the settings (config file, --student, --lrs) before the work, so that a mistake is named
// before the drilling rather than after it. The one learning-record failure that is the command's.
Status checkLearningOptions(const LearningCliOptions& o);
// THE way score, demo and run record a scored attempt: stampStatementId, then recordAttempt, before
// the report is written (again), so that the written report names its statement. Any failure is one
// warning line ("the attempt was not recorded: ..."), never the command's: the attempt was scored.
void recordAttemptOrWarn(const LearningCliOptions& o, const Task& task, nlohmann::ordered_json& report,
                         const std::string& session_file, const std::string& final_file);
// The same for a hook that hands a report it may not change: recorded, and the report not stamped.
void recordAttemptOrWarn(const LearningCliOptions& o, const Task& task, const nlohmann::ordered_json& report,
                         const std::string& session_file, const std::string& final_file);

// Who the records are for and where they are kept, resolved as recordAttempt resolves them (the
// flags, then the config file, then the defaults), for the simulator's student start: the task
// picker's attempts and the Score page's last attempts (eval/student_records.h). `config_path` is
// the config file read (or that would be read): a name typed at the first-run prompt is kept there.
struct LearnerSettings {
  LearnerContext learner;    // student (empty: none named), course id, activity base
  std::string outbox;        // the outbox file
  std::string config_path;   // --config, else $DENTSIM_CONFIG, else the default place
};
Result<LearnerSettings> learnerSettings(const LearningCliOptions& o);

// The school's LRS as `report --lrs` reads it: the endpoint with the credentials sending uses (the
// config file's, or DENTSIM_LRS_USERNAME/PASSWORD; never the command line), and the activity IRI of
// the course whose statements are wanted, as recordAttempt names it in each statement's context.
struct LrsReadSettings {
  LrsEndpoint lrs;              // o.lrs, else the config's; a page's answer may take up to 30 s
  std::string course;           // o.course, else the config's, else "builtin"
  std::string course_activity;  // the course's activity IRI under the config's activity base
};
// Errors: a malformed config, no LRS named, an LRS URL that is not http or https.
Result<LrsReadSettings> lrsForReading(const LearningCliOptions& o);

// Sends the outbox's pending statements when an LRS is named (--lrs or the config), for at most
// 10 s in all and never while another dentsim is sending; prints what was delivered, or a one-line
// warning when the LRS could not take them (they stay pending) or the outbox could not be read.
// Only settings that checkLearningOptions would have refused are an error.
Status sendPendingIfConfigured(const LearningCliOptions& o);

}  // namespace dentsim::app
