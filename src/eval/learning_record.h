// Learning records: one scored attempt as an xAPI 1.0.3 statement, built from the score report's summary and the attempt's facts, with its stable name-based id.
//
// Pure: no files, no network. The outbox that keeps the statements and the client that sends them
// are io's (io/xapi_outbox.h, io/lrs_client.h); app/learning_cli.h joins them for the commands.
// docs/LEARNING_RECORDS.md describes every field and IRI; the class report reads what this writes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/score_summary.h"
#include "eval/task.h"

namespace dentsim {

// ---- The IRIs: each rule in one place ----------------------------------------------------------------

// The activity base when the school names none. The ".invalid" domain can never be registered, so
// these IRIs name dentsim without claiming anyone's web site.
inline constexpr const char* kDefaultActivityBase = "https://dentsim.invalid/xapi";
// The account's home page when the school names none.
inline constexpr const char* kDefaultHomePage = "https://dentsim.invalid";
// Every result extension's key is this base followed by its name ("removed-mm3", ...). Fixed, not
// configurable, so that a class report finds the same keys whichever school wrote them.
inline constexpr const char* kExtensionBase = "https://dentsim.invalid/xapi/extensions/";
inline constexpr const char* kVerbBase = "http://adlnet.gov/expapi/verbs/";

// "<activity base>/courses/<course>" and "<activity base>/courses/<course>/tasks/<task>"; a trailing
// '/' on the base is dropped. Course and task are plain names (isPlainName), so they need no escaping.
std::string courseActivityIri(const std::string& activity_base, const std::string& course);
std::string taskActivityIri(const std::string& activity_base, const std::string& course, const std::string& task);
// kExtensionBase + name.
std::string extensionIri(const std::string& name);

// ---- The attempt --------------------------------------------------------------------------------------

// Who did it and where: the learner's and the school's side of a statement.
struct LearnerContext {
  std::string student;                     // the account name (a student number); required
  std::string student_name;                // display name; empty: none in the statement
  std::string home_page = kDefaultHomePage;  // the account's homePage (an IRI)
  std::string course = "builtin";          // course id, a plain name
  std::string activity_base = kDefaultActivityBase;
  std::string language = "en-US";          // the language of the task's title and instructions (RFC 5646)
};

// What the statement needs beyond the report.
struct AttemptFacts {
  // The attempt's identity: XXH3 of the session file (hex), or of the final tooth file when no
  // session was scored. Same attempt, same key.
  std::string attempt_key;
  std::optional<std::string> session_hash;  // XXH3 of the session file (hex); none without a session
  std::string timestamp;                    // when the attempt ended, ISO 8601 UTC ("2026-11-27T07:00:00Z")
};

// The verb an attempt gets: "passed"/"failed" against the task's pass mark, "completed" without one.
enum class AttemptVerb { Completed, Passed, Failed };
AttemptVerb attemptVerb(const Task& task, double total);
const char* attemptVerbName(AttemptVerb verb);

// The statement of one scored attempt. `score` is what the "dentsim-score" report that scoreCut made
// for `task` says. Errors (one line) name what is missing: no student, a course that is not a plain name.
Result<nlohmann::ordered_json> buildStatement(const Task& task, const ScoreReportSummary& score,
                                              const LearnerContext& learner, const AttemptFacts& facts);
// The same from the whole report; also an error when the report is not one (the key named).
Result<nlohmann::ordered_json> buildStatement(const Task& task, const nlohmann::ordered_json& report,
                                              const LearnerContext& learner, const AttemptFacts& facts);

// The statement id: a version-5 (SHA-1, name-based) UUID of "<attempt_key>|<task>|<student>" in
// dentsim's namespace (itself the version-5 UUID of kDefaultActivityBase in the URL namespace), so
// the same attempt by the same student always gets the same id.
std::string statementId(const std::string& attempt_key, const std::string& task, const std::string& student);

// An ISO 8601 duration with centisecond precision, as xAPI asks: 75.5 -> "PT1M15.5S", 3600 -> "PT1H0S".
std::string isoDuration(double seconds);

// ---- The pieces, for the tests ------------------------------------------------------------------------

// RFC 4122 version-5 UUID of `name` in the namespace `ns` (a UUID in its text form), lower-case text.
std::string uuidV5(const std::string& ns, const std::string& name);

}  // namespace dentsim
