// Reading a class's attempts for the class report: score reports (score.json) and outboxes of xAPI statements, as one list.
//
// docs/CLASS_REPORT.md gives the formats and the rules below. A score report holds no student and
// no time of its own, so both come from around it: the `student` and `timestamp` fields when the
// report has them, else the caller's student, else the folder layout STUDENT/ATTEMPT/score.json
// (the student is the folder two above the file); the time is the file's modification time. An
// outbox is JSON lines, one xAPI 1.0.3 statement per line; statements with no score (launched,
// attempted) are counted and left out. A line of an outbox that is not a statement (a torn write, a
// hand edit) is left out with a warning naming the file and line, and the rest are read; a file with
// no statement at all is an error. Every error and warning is one line naming the file (and the line).
// The score's parts, the time taken and the surface agreement come from the report's keys, read
// through its typed summary (eval/score_summary.h), or from a statement's result extensions
// (eval/learning_record.h) that copy them; they are read leniently, since the scoring's parts change
// between versions: what is not a number is left out.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/result.h"

namespace dentsim {

// One part of the score: a component of the paper's table, or a deduction from the total.
struct AttemptPart {
  std::string name;                    // the report's key: "undercut", "time", "force", "healthy", "adjacent", "pulp_exposure"
  bool deduction = false;              // taken off the total (the report's `deductions`), not earned
  std::optional<double> points;        // a component's points earned, a deduction's points taken off [points]; none: not scored, or a cap
  std::optional<double> max;           // a component's most [points]; none for a deduction
  std::optional<double> cap;           // a cap that applied: the total was held to this [points of total_max]
  std::optional<double> earned_share;  // a part earned in proportion to the work done: the share that counted, [0, 1]
};

// How well the student's surface matches the ideal cavity's (docs/SCORING.md, surface agreement).
struct AttemptAgreement {
  double band_mm = 0.0;                // the tolerance band, plus or minus [mm]
  double within_percent = 0.0;         // the ideal surface's share matched within the band [%]
};

// One scored attempt at a task, from either source.
struct ClassAttempt {
  std::string student;                 // the student's id (account name, mbox, or the report's student)
  std::string student_name;            // what to show; the id when no name is known
  std::string task;                    // the task's name ("class2_cavity"): a report's task.name, a statement's last IRI segment
  std::string task_title;              // the task's title; the name when none is known
  std::string task_kind;               // "caries", "cavity", "access", "crown"; empty when unknown (statements)
  double score = 0.0;                  // [points of 100], [0, 100]
  double time_s = 0.0;                 // when the attempt ended [s since 1970-01-01 UTC]
  std::optional<double> duration_s;    // how long it took [s], when said
  std::optional<bool> success;         // a statement's result.success, when said
  std::string verb;                    // the statement's verb ("passed", "failed", "completed"); "scored" for a report
  bool pulp_exposed = false;           // the cut reached the pulp
  bool adjacent_damaged = false;       // the cut damaged an adjacent tooth (above the noise floor; docs/SCORING.md)
  bool guided = false;                 // a guide's spring pulled the drill (a report's "guided", a statement's guided extension)
  std::string picture;                 // the score picture's file; empty when there is none
  std::string source;                  // where it was read: "path" or "path:line"
  std::string statement_id;            // the statement's "id" (a UUID), or the score report's "statement_id"; empty: none
  bool from_statement = false;         // read from an outbox's statement; false: a score report
  std::optional<double> total_max;     // what the scored parts could give [points]: the report's total_max, a statement's total-max
  std::vector<AttemptPart> parts;      // components, then deductions, in the report's order; empty when not said
  std::optional<AttemptAgreement> agreement;  // cavity and access: the surface agreement, when said
};

// What a caller knows about score reports that the reports do not say.
struct AttemptReadOptions {
  std::string student;                 // every score report given is this student's; empty: the report's or the folders'
};

// A whole input file's attempts. A file is a score report when it is one JSON object whose
// "format" is "dentsim-score"; otherwise it is read as an outbox. `skipped` (may be null) counts
// the statements left out for having no score; `warnings` (may be null) gains one line per outbox
// line left out ("outbox.jsonl:3: not a JSON statement (malformed JSON); line left out").
Result<std::vector<ClassAttempt>> readAttempts(const std::string& path, const AttemptReadOptions& options, int* skipped,
                                                std::vector<std::string>* warnings = nullptr);

// ---- the parts, for tests ------------------------------------------------------------------------

// A score report's text. `file_time_s` is the file's modification time, used when the report has
// no "timestamp"; `picture` the score.png beside it ("" when there is none).
Result<ClassAttempt> parseScoreReport(const std::string& text, const std::string& path, double file_time_s,
                                 const std::string& picture, const AttemptReadOptions& options);
// Calls row(line, text) for each line of `text` that is not blank (spaces, tabs, a CR), numbered
// from 1: how the JSON-lines readers (an outbox, a student's records) walk a file.
template <class Row>
void forEachJsonLine(const std::string& text, Row row) {
  size_t begin = 0;
  for (int line = 1; begin < text.size(); ++line) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string one = text.substr(begin, end - begin);
    begin = end + 1;
    if (one.find_first_not_of(" \t\r") != std::string::npos) row(line, one);
  }
}

// An outbox's text, line by line (blank lines are allowed). Relative picture paths are taken from
// `folder`; `file_time_s` stands in for a statement's missing timestamp. A bad line is left out with
// a warning (readAttempts); the error, when not one line is a statement, is the first bad line's.
Result<std::vector<ClassAttempt>> parseStatements(const std::string& text, const std::string& path, const std::string& folder,
                                             double file_time_s, int* skipped, std::vector<std::string>* warnings = nullptr);
// The parts of a score from a report's `components` and `deductions` objects (or the same two in a
// statement's parts extension). A component needs a number `max` and a number or null `points`; a
// deduction a number or null `points`, or a `cap` and `applied` (kept only when it applied).
// Anything else is left out: a field a later version adds does not make a report unreadable.
std::vector<AttemptPart> readParts(const nlohmann::ordered_json& components, const nlohmann::ordered_json& deductions);
// An ISO 8601 date and time ("2026-11-27T08:15:00.5Z", "...+01:00"; no zone means UTC) in seconds
// since 1970-01-01 UTC; none when the text is not one.
std::optional<double> parseIsoTime(const std::string& text);
// An ISO 8601 duration ("PT5M12.5S", "P1DT2H") in seconds; none when the text is not one.
std::optional<double> parseIsoDuration(const std::string& text);
// The student a score report's path names by the layout STUDENT/ATTEMPT/score.json; empty when the
// path has no two folders above the file.
std::string studentFromLayout(const std::string& path);

}  // namespace dentsim
