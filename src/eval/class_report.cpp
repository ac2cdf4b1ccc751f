// Groups a class's attempts into the class report's model: per task, per student, and the flagged attempts.
#include "eval/class_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

#include "core/percentile.h"
#include "eval/cut_score.h"
#include "eval/task_kinds.h"

namespace dentsim {

int scoreBin(double score) { return std::clamp(int(score / 10.0), 0, kScoreBins - 1); }

// The teacher's marks on the command line win; otherwise a built-in task's own `pass_mark`.
std::optional<double> passMarkFor(const ClassReportOptions& options, const std::string& task) {
  if (auto it = options.task_pass_marks.find(task); it != options.task_pass_marks.end()) return it->second;
  if (options.pass_mark) return options.pass_mark;
  const std::vector<std::string> names = builtinTaskNames();
  if (std::find(names.begin(), names.end(), task) == names.end()) return std::nullopt;
  auto t = builtinTask(task);
  return t ? t->pass_mark : std::nullopt;
}

namespace {

// The kind of a task a statement names, when it is a built-in one (statements do not carry it).
std::string builtinKind(const std::string& task) {
  const std::vector<std::string> names = builtinTaskNames();
  if (std::find(names.begin(), names.end(), task) == names.end()) return "";
  auto t = builtinTask(task);
  return t ? taskKindName(t->kind) : "";
}

std::vector<std::string> reasonsFor(const ClassAttempt& a, const std::optional<double>& pass_mark) {
  std::vector<std::string> reasons;
  // An unknown kind (a statement of a task from elsewhere) is held to the usual rule.
  const TaskKindRow* kind = findTaskKind(a.task_kind);
  if (a.pulp_exposed && (!kind || kind->pulp == PulpRule::ExposureCaps)) reasons.push_back("pulp exposed");
  // Every kind: an adjacent tooth is never part of the exercise.
  if (a.adjacent_damaged) reasons.push_back("adjacent tooth damaged");
  if (pass_mark && a.score < *pass_mark) {
    char text[64];
    std::snprintf(text, sizeof text, "below the pass mark of %g", *pass_mark);
    reasons.push_back(text);
  }
  if (a.verb == "failed" || (a.success && !*a.success)) reasons.push_back("failed");
  return reasons;
}

}  // namespace

std::optional<double> pointsLost(const AttemptPart& part) {
  if (!part.points) return std::nullopt;
  if (part.deduction) return std::max(0.0, *part.points);
  return part.max ? std::optional<double>(std::max(0.0, *part.max - *part.points)) : std::nullopt;
}

std::optional<double> lostShare(const AttemptPart& part, const std::optional<double>& total_max) {
  if (part.cap) return 1.0;
  const std::optional<double> lost = pointsLost(part);
  if (!lost) return std::nullopt;
  const double whole = part.deduction ? total_max.value_or(100.0) : part.max.value_or(0.0);
  return whole > 0 ? std::clamp(*lost / whole, 0.0, 1.0) : 0.0;
}

void mergeStatement(ClassAttempt& report, const ClassAttempt& statement) {
  report.student = statement.student;
  report.student_name = statement.student_name;
  report.time_s = statement.time_s;
  // A verdict belongs to the score it was given for; a report scored again keeps its own "scored".
  if (std::abs(statement.score - report.score) < 1e-6) {
    report.verb = statement.verb;
    report.success = statement.success;
  }
  if (!report.duration_s) report.duration_s = statement.duration_s;
  if (!report.total_max) report.total_max = statement.total_max;
  if (report.parts.empty()) report.parts = statement.parts;
  if (!report.agreement) report.agreement = statement.agreement;
  if (report.task_kind.empty()) report.task_kind = statement.task_kind;
  if (report.picture.empty()) report.picture = statement.picture;
  // A report of a tooth without neighbours says nothing; a statement of the same attempt cannot say more.
  report.adjacent_damaged = report.adjacent_damaged || statement.adjacent_damaged;
  report.source += ", " + statement.source;
}

ClassReport buildClassReport(std::vector<ClassAttempt> attempts, const ClassReportOptions& options) {
  ClassReport r;
  // Reports first, so that the rule does not hang on the order the files were named in.
  std::stable_partition(attempts.begin(), attempts.end(), [](const ClassAttempt& a) { return !a.from_statement; });
  std::map<std::string, size_t> report_of;  // statement id -> its score report's place in `kept`
  std::set<std::string> statement_ids;
  std::vector<ClassAttempt> kept;
  for (ClassAttempt& a : attempts) {
    if (a.statement_id.empty()) {
      kept.push_back(std::move(a));
    } else if (!a.from_statement) {
      if (report_of.emplace(a.statement_id, kept.size()).second) kept.push_back(std::move(a));
      else ++r.duplicates;  // the same report twice: a copied folder
    } else if (!statement_ids.insert(a.statement_id).second) {
      ++r.duplicates;  // the same statement twice: two copies of an outbox
    } else if (const auto it = report_of.find(a.statement_id); it != report_of.end()) {
      mergeStatement(kept[it->second], a);
      ++r.merged;
    } else {
      kept.push_back(std::move(a));
    }
  }
  attempts = std::move(kept);
  std::map<std::string, std::string> kinds;  // built-in kinds looked up once per task
  for (ClassAttempt& a : attempts)
    if (a.task_kind.empty()) {
      auto [it, fresh] = kinds.try_emplace(a.task);
      if (fresh) it->second = builtinKind(a.task);
      a.task_kind = it->second;
    }
  std::stable_sort(attempts.begin(), attempts.end(), [](const ClassAttempt& x, const ClassAttempt& y) {
    return std::tie(x.time_s, x.student, x.source) < std::tie(y.time_s, y.student, y.source);
  });
  r.attempts = std::move(attempts);
  if (!r.attempts.empty()) {
    r.first_s = r.attempts.front().time_s;
    r.last_s = r.attempts.back().time_s;
  }

  // Students: the latest name each id went by.
  std::map<std::string, StudentSummary> students;
  std::map<std::string, std::set<std::string>> tasks_of;
  for (const ClassAttempt& a : r.attempts) {
    StudentSummary& s = students[a.student];
    s.id = a.student;
    s.name = a.student_name.empty() ? a.student : a.student_name;
    ++s.attempts;
    tasks_of[a.student].insert(a.task);
  }
  for (auto& [id, s] : students) {
    s.tasks = int(tasks_of[id].size());
    r.students.push_back(s);
  }
  // By name as a teacher reads a list: "ben" before "Chloé", whatever the case.
  auto folded = [](std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
  };
  std::sort(r.students.begin(), r.students.end(), [&](const StudentSummary& x, const StudentSummary& y) {
    return std::make_tuple(folded(x.name), x.name, x.id) < std::make_tuple(folded(y.name), y.name, y.id);
  });

  // Tasks: counts, bins, spread.
  std::map<std::string, TaskSummary> tasks;
  std::map<std::string, std::vector<double>> scores;
  for (const ClassAttempt& a : r.attempts) {
    TaskSummary& t = tasks[a.task];
    t.name = a.task;
    t.title = a.task_title;
    ++t.attempts;
    ++t.bins[size_t(scoreBin(a.score))];
    scores[a.task].push_back(a.score);
  }
  for (auto& [name, t] : tasks) {
    t.pass_mark = passMarkFor(options, name);
    const std::vector<double>& v = scores[name];
    t.min = *std::min_element(v.begin(), v.end());
    t.max = *std::max_element(v.begin(), v.end());
    t.median = percentile(v, 50.0);
    for (const StudentSummary& s : r.students)
      if (tasks_of[s.id].count(name)) t.students.push_back(s.id);
    r.tasks.push_back(t);
  }

  for (size_t i = 0; i < r.attempts.size(); ++i) {
    std::vector<std::string> reasons = reasonsFor(r.attempts[i], passMarkFor(options, r.attempts[i].task));
    if (!reasons.empty()) r.flags.push_back({i, std::move(reasons)});
  }
  return r;
}

std::vector<size_t> attemptsOf(const ClassReport& report, const std::string& student, const std::string& task) {
  std::vector<size_t> out;
  for (size_t i = 0; i < report.attempts.size(); ++i)
    if (report.attempts[i].student == student && report.attempts[i].task == task) out.push_back(i);
  return out;
}

}  // namespace dentsim
