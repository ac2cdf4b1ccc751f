// Reading one student's attempts from the outbox: the lines filtered by actor and activity, each parsed as the class report parses it.
#include "eval/student_records.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/learning_config.h"
#include "io/strict_json.h"

namespace dentsim {
namespace {

using json = nlohmann::json;

// An outbox grows by one line an attempt; a lab PC's in years stays far below this.
constexpr uint64_t kMaxOutboxBytes = 64ull << 20;  // [bytes]
// io/learning_config.h reads at most this much of a config file.
constexpr uint64_t kMaxConfigBytes = 64u << 10;  // [bytes]

std::string accountName(const json& st) {
  const auto actor = st.find("actor");
  if (actor == st.end() || !actor->is_object()) return "";
  const auto account = actor->find("account");
  if (account == actor->end() || !account->is_object()) return "";
  const auto name = account->find("name");
  return name != account->end() && name->is_string() ? name->get<std::string>() : "";
}

std::string objectId(const json& st) {
  const auto object = st.find("object");
  if (object == st.end() || !object->is_object()) return "";
  const auto id = object->find("id");
  return id != object->end() && id->is_string() ? id->get<std::string>() : "";
}

}  // namespace

StudentRecords parseStudentRecords(const std::string& text, const std::string& path, const std::string& student) {
  StudentRecords r;
  r.student = student;
  if (student.empty()) return r;
  forEachJsonLine(text, [&](int line, const std::string& row) {
    // Another student's line is none of this one's business, even a damaged one: only lines that
    // parse and name this student are read further.
    const json st = json::parse(row, nullptr, false);
    if (st.is_discarded() || !st.is_object() || accountName(st) != student) return;
    const std::string activity = objectId(st);
    if (activity.empty()) return;
    // The class report's own statement reader, so the two never read an attempt differently.
    // One row alone: a bad statement is the error (its problem after parseStatements' "path:1: ").
    auto parsed = parseStatements(row, path, ".", 0.0, nullptr);
    if (!parsed) {
      const std::string& why = parsed.message();
      const size_t at = why.find(": ", path.size());
      r.warnings.push_back(path + ":" + std::to_string(line) + (at == std::string::npos ? ": " + why : why.substr(at)) +
                           "; line left out");
      return;
    }
    for (ClassAttempt& a : *parsed) {
      a.source = path + ":" + std::to_string(line);
      r.by_activity[activity].push_back(std::move(a));
    }
  });
  // Oldest first by time; the outbox's order (stable) among equal times.
  for (auto& [activity, list] : r.by_activity)
    std::stable_sort(list.begin(), list.end(), [](const ClassAttempt& a, const ClassAttempt& b) { return a.time_s < b.time_s; });
  return r;
}

Result<StudentRecords> readStudentRecords(const std::string& outbox, const std::string& student) {
  std::error_code ec;
  if (student.empty() || !std::filesystem::exists(outbox, ec)) {
    StudentRecords none;
    none.student = student;
    return none;
  }
  auto bytes = readFileBytes(outbox, kMaxOutboxBytes);
  if (!bytes) return bytes.error();
  return parseStudentRecords(std::string(bytes->begin(), bytes->end()), outbox, student);
}

TaskRecord taskRecord(const StudentRecords& records, const std::string& activity_iri) {
  TaskRecord t;
  const auto it = records.by_activity.find(activity_iri);
  if (it == records.by_activity.end()) return t;
  const std::vector<ClassAttempt>& all = it->second;
  t.attempts = int(all.size());
  for (const ClassAttempt& a : all) t.best = t.best ? std::max(*t.best, a.score) : a.score;
  const size_t first = all.size() > kRecentAttempts ? all.size() - kRecentAttempts : 0;
  t.recent.assign(all.begin() + long(first), all.end());
  return t;
}

bool taskPassed(const TaskRecord& record, const std::optional<double>& pass_mark) {
  return pass_mark && record.best && *record.best >= *pass_mark;
}

Status keepStudentName(const std::string& config_path, const std::string& student) {
  if (const std::string problem = studentNameProblem(student, kMaxStudentIdBytes); !problem.empty())
    return Error{"the student's name " + quotedForMessage(student) + " " + problem};
  namespace fs = std::filesystem;
  std::error_code ec;
  nlohmann::ordered_json config = nlohmann::ordered_json::object();
  if (fs::exists(config_path, ec)) {
    auto bytes = readFileBytes(config_path, kMaxConfigBytes);
    if (!bytes) return bytes.error();
    config = nlohmann::ordered_json::parse(bytes->begin(), bytes->end(), nullptr, false);
    // Never replace a file the student cannot see into: a hand-edited config with a typo stays as it is.
    if (config.is_discarded() || !config.is_object())
      return makeError(config_path, "not a JSON object; the name was not kept (fix or remove the file)");
  }
  config["student"] = student;
  const fs::path folder = fs::path(config_path).parent_path();
  if (!folder.empty()) fs::create_directories(folder, ec);
  if (Status st = writeFileAtomic(config_path, config.dump(2) + "\n"); !st) return st;
  fs::permissions(config_path, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace, ec);
  // What was written must read back as a config, or the next run would refuse to start.
  if (auto back = loadLearningConfig(config_path); !back) return back.error();
  return Ok{};
}

}  // namespace dentsim
