// The class report's page model: a class's attempts grouped by student and task, each task's score distribution, and the attempts a teacher should look at.
//
// eval/attempt_reader.h reads the attempts; eval/class_report_html.h draws this model as one HTML
// page. Nothing here reads or writes a file.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"

namespace dentsim {

// Pass marks: tasks carry none, so the teacher gives them.
struct ClassReportOptions {
  std::optional<double> pass_mark;               // every task's [points of 100]; none: no pass mark
  std::map<std::string, double> task_pass_marks; // by task name; wins over pass_mark
};

// Ten bins of ten points: [0, 10), [10, 20), ..., [90, 100] (100 falls in the last).
constexpr int kScoreBins = 10;
int scoreBin(double score);

struct TaskSummary {
  std::string name;                        // the task's name
  std::string title;                       // its title as the latest attempt gave it
  std::optional<double> pass_mark;         // [points of 100]
  int attempts = 0;                        // attempts at this task
  std::array<int, kScoreBins> bins{};      // attempts per score bin (scoreBin)
  double min = 0.0, median = 0.0, max = 0.0;  // of the scores; median by the nearest-rank rule (core/percentile.h)
  std::vector<std::string> students;       // ids of the students who tried it, in ClassReport::students' order
};

struct StudentSummary {
  std::string id;                          // the student's id
  std::string name;                        // the latest name the attempts gave
  int attempts = 0;                        // all tasks
  int tasks = 0;                           // distinct tasks tried
};

// An attempt a teacher should look at, and why: "pulp exposed", "adjacent tooth damaged", "below the
// pass mark of 50", "failed" (verb failed or success false). An access cavity must open the pulp, so
// there it is no fault; an adjacent tooth is a fault in every kind.
struct FlaggedAttempt {
  size_t attempt = 0;                      // index into ClassReport::attempts
  std::vector<std::string> reasons;        // one or more, in that order
};

struct ClassReport {
  std::vector<ClassAttempt> attempts;      // by time, then student, then source; one per attempt (see buildClassReport)
  std::vector<TaskSummary> tasks;          // by name
  std::vector<StudentSummary> students;    // by name (ASCII case folded), then id
  std::vector<FlaggedAttempt> flags;       // in the attempts' order
  double first_s = 0.0, last_s = 0.0;      // the earliest and latest attempt [s since the epoch]
  int duplicates = 0;                      // statements or reports left out for an id seen before (two copies of an outbox)
  int merged = 0;                          // statements merged into the score report that carries their id
};

// One attempt, one row. A score report whose `statement_id` is a statement's id is the same attempt:
// the two merge into one row (mergeStatement). Among reports, and among statements, an id that came
// before (in the order given) is a copy, counted in `duplicates` and left out.
ClassReport buildClassReport(std::vector<ClassAttempt> attempts, const ClassReportOptions& options);

// A score report and its statement as one attempt. The report keeps its score (it may have been
// scored again since), picture, parts, agreement, kind and source; the statement gives the student
// (its id was made from the account), the name, the time it was scored, and its verdict (verb and
// success) when it was given for the report's score. What the report lacks (time taken, parts,
// agreement) the statement fills in; `source` names both files.
void mergeStatement(ClassAttempt& report, const ClassAttempt& statement);

// What a part cost [points]: a component's max less its points, a deduction's points; none when it
// was not scored, and none for a cap that applied (the part alone does not say what it took).
std::optional<double> pointsLost(const AttemptPart& part);
// A part's loss in [0, 1], for the page's colours: a component's of its own max, a deduction's of
// the attempt's total_max (100 when not said); 1 for a cap that applied; none when not scored.
std::optional<double> lostShare(const AttemptPart& part, const std::optional<double>& total_max);

// The indices (into report.attempts, oldest first) of one student's attempts at one task.
std::vector<size_t> attemptsOf(const ClassReport& report, const std::string& student, const std::string& task);

// The pass mark of a task under these options; none when neither gives one.
std::optional<double> passMarkFor(const ClassReportOptions& options, const std::string& task);

}  // namespace dentsim
