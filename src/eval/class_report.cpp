// Groups a class's attempts into the class report's model: per task, per student, and the flagged attempts.
#include "eval/class_report.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>
#include <tuple>

#include "core/percentile.h"
#include "eval/cut_score.h"

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
  if (a.pulp_exposed && a.task_kind != "access") reasons.push_back("pulp exposed");
  if (pass_mark && a.score < *pass_mark) {
    char text[64];
    std::snprintf(text, sizeof text, "below the pass mark of %g", *pass_mark);
    reasons.push_back(text);
  }
  if (a.verb == "failed" || (a.success && !*a.success)) reasons.push_back("failed");
  return reasons;
}

}  // namespace

ClassReport buildClassReport(std::vector<ClassAttempt> attempts, const ClassReportOptions& options) {
  ClassReport r;
  // The outbox gives each statement an id; the same id twice is one attempt read twice.
  std::set<std::string> ids;
  std::vector<ClassAttempt> kept;
  for (ClassAttempt& a : attempts) {
    if (!a.statement_id.empty() && !ids.insert(a.statement_id).second) ++r.duplicates;
    else kept.push_back(std::move(a));
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
