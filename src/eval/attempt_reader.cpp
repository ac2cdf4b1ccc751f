// Reads score reports and xAPI outboxes into one list of attempts (see attempt_reader.h for the rules).
//
// Contents: 1. ISO 8601 times and durations  2. score reports  3. statements  4. a whole file
#include "eval/attempt_reader.h"

#include <sys/stat.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/text_escape.h"
#include "eval/score_summary.h"
#include "io/atomic_file.h"

namespace dentsim {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;  // ordered: a report's parts keep their order on the page

namespace {

// Input files are class records, not tooth volumes: 64 MiB holds years of a lab's statements.
constexpr uint64_t kMaxInputBytes = 64ull << 20;

// ---- 1. ISO 8601 times and durations --------------------------------------------------------------

// Reads exactly `digits` decimal digits at s[*at]; false when they are not there.
bool readDigits(std::string_view s, size_t* at, int digits, int* value) {
  if (*at + size_t(digits) > s.size()) return false;
  int v = 0;
  for (int i = 0; i < digits; ++i) {
    const char c = s[*at + size_t(i)];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  *at += size_t(digits);
  *value = v;
  return true;
}

// Days from 1970-01-01 to the given proleptic Gregorian date. Years are shifted to start in March,
// so that the leap day falls at the end of the shifted year and months have a closed form.
int64_t daysSinceEpoch(int year, int month, int day) {
  const int64_t y = year - (month <= 2 ? 1 : 0);
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t year_of_era = y - era * 400;                                  // [0, 399]
  const int64_t shifted_month = month > 2 ? month - 3 : month + 9;            // March = 0
  const int64_t day_of_year = (153 * shifted_month + 2) / 5 + day - 1;        // [0, 365]
  const int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;                                  // 719468: 0000-03-01 to 1970-01-01
}

bool leapYear(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
int daysInMonth(int y, int m) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leapYear(y) ? 29 : kDays[m - 1];
}

// A modification time [s since the epoch]; 0 when the file cannot be stat'ed (it was just read).
double fileTime(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0.0;
  return double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec);
}

}  // namespace

std::optional<double> parseIsoTime(const std::string& text) {
  const std::string_view s = text;
  size_t at = 0;
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  auto expect = [&](char c) { return at < s.size() && s[at++] == c; };
  if (!readDigits(s, &at, 4, &year) || !expect('-') || !readDigits(s, &at, 2, &month) || !expect('-') ||
      !readDigits(s, &at, 2, &day))
    return std::nullopt;
  if (at >= s.size() || (s[at] != 'T' && s[at] != 't' && s[at] != ' ')) return std::nullopt;
  ++at;
  if (!readDigits(s, &at, 2, &hour) || !expect(':') || !readDigits(s, &at, 2, &minute) || !expect(':') ||
      !readDigits(s, &at, 2, &second))
    return std::nullopt;
  if (month < 1 || month > 12 || day < 1 || day > daysInMonth(year, month) || hour > 23 || minute > 59 || second > 60)
    return std::nullopt;
  double fraction = 0.0;
  if (at < s.size() && (s[at] == '.' || s[at] == ',')) {
    ++at;
    double scale = 0.1;
    const size_t first = at;
    for (; at < s.size() && std::isdigit(static_cast<unsigned char>(s[at])); ++at, scale *= 0.1) fraction += scale * (s[at] - '0');
    if (at == first) return std::nullopt;
  }
  // The zone: Z, +HH:MM, +HHMM or none (UTC, as the xAPI outbox writes it).
  int offset_min = 0;
  if (at < s.size()) {
    if (s[at] == 'Z' || s[at] == 'z') {
      ++at;
    } else if (s[at] == '+' || s[at] == '-') {
      const int sign = s[at++] == '-' ? -1 : 1;
      int oh = 0, om = 0;
      if (!readDigits(s, &at, 2, &oh)) return std::nullopt;
      if (at < s.size() && s[at] == ':') ++at;
      if (!readDigits(s, &at, 2, &om) || oh > 23 || om > 59) return std::nullopt;
      offset_min = sign * (oh * 60 + om);
    } else {
      return std::nullopt;
    }
  }
  if (at != s.size()) return std::nullopt;
  const int64_t days = daysSinceEpoch(year, month, day);
  const int64_t secs = days * 86400 + hour * 3600 + minute * 60 + second - int64_t(offset_min) * 60;
  return double(secs) + fraction;
}

std::optional<double> parseIsoDuration(const std::string& text) {
  const std::string_view s = text;
  if (s.size() < 2 || s[0] != 'P') return std::nullopt;
  double total = 0.0;
  bool in_time = false, any = false;
  size_t at = 1;
  while (at < s.size()) {
    if (s[at] == 'T') {
      if (in_time) return std::nullopt;
      in_time = true;
      ++at;
      continue;
    }
    const size_t first = at;
    while (at < s.size() && (std::isdigit(static_cast<unsigned char>(s[at])) || s[at] == '.')) ++at;
    if (at == first || at >= s.size()) return std::nullopt;
    double value = 0.0;
    if (std::sscanf(std::string(s.substr(first, at - first)).c_str(), "%lf", &value) != 1 || !std::isfinite(value))
      return std::nullopt;
    const char unit = s[at++];
    // Years and months have no fixed length; a class's attempts are minutes long, so they are refused.
    if (!in_time && unit == 'W') total += value * 7 * 86400;
    else if (!in_time && unit == 'D') total += value * 86400;
    else if (in_time && unit == 'H') total += value * 3600;
    else if (in_time && unit == 'M') total += value * 60;
    else if (in_time && unit == 'S') total += value;
    else return std::nullopt;
    any = true;
  }
  if (!any) return std::nullopt;
  return total;
}

std::string studentFromLayout(const std::string& path) {
  const fs::path p = fs::absolute(fs::path(path)).lexically_normal();
  const fs::path attempt = p.parent_path();
  const fs::path student = attempt.parent_path();
  if (attempt == attempt.root_path() || student == student.root_path()) return "";
  return student.filename().string();
}

// ---- 2. score reports -----------------------------------------------------------------------------

namespace {

// A finite number at `key` of an object; none otherwise (missing, null, text, not an object).
std::optional<double> numberAt(const json& j, const char* key) {
  if (!j.is_object()) return std::nullopt;
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number() || !std::isfinite(it->get<double>())) return std::nullopt;
  return it->get<double>();
}

// A surface agreement needs its band and its share within; the other shares are the picture's.
// No samples (no ideal surface to measure at) is no agreement, not 0 % of one.
std::optional<AttemptAgreement> agreementOf(const json& j) {
  const auto band = numberAt(j, "band_mm"), within = numberAt(j, "within_percent"), samples = numberAt(j, "samples");
  if (!band || !within || (samples && *samples <= 0)) return std::nullopt;
  return AttemptAgreement{*band, *within};
}

}  // namespace

std::vector<AttemptPart> readParts(const json& components, const json& deductions) {
  std::vector<AttemptPart> parts;
  if (components.is_object())
    for (const auto& [name, c] : components.items()) {
      // A component not scored says so with "points": null; one with no "points" key is not a part.
      if (!c.is_object() || !c.contains("points") || !(c["points"].is_null() || numberAt(c, "points"))) continue;
      AttemptPart p;
      p.name = name;
      p.max = numberAt(c, "max");
      if (!p.max) continue;
      p.points = numberAt(c, "points");
      p.earned_share = numberAt(c, "earned_share");
      parts.push_back(std::move(p));
    }
  if (deductions.is_object())
    for (const auto& [name, d] : deductions.items()) {
      if (!d.is_object()) continue;
      AttemptPart p;
      p.name = name;
      p.deduction = true;
      if (d.contains("points") && (d["points"].is_null() || numberAt(d, "points"))) {
        p.points = numberAt(d, "points");
      } else if (d.value("applied", json()).is_boolean() && numberAt(d, "cap")) {
        // A cap that did not apply took nothing off, and there is nothing to show for it.
        if (!d["applied"].get<bool>()) continue;
        p.cap = numberAt(d, "cap");
      } else {
        continue;
      }
      parts.push_back(std::move(p));
    }
  return parts;
}

namespace {

// A report's parts as the page shows them, by readParts' rules: a component with its points (or
// null) and its max; a deduction with its points (or null), or a cap that applied.
std::vector<AttemptPart> attemptPartsOf(const std::vector<ScoreReportPart>& parts) {
  std::vector<AttemptPart> out;
  for (const ScoreReportPart& r : parts) {
    AttemptPart p;
    p.name = r.name;
    p.deduction = r.deduction;
    if (!r.deduction) {
      if (!r.has_points || !r.max) continue;
      p.points = r.points;
      p.max = r.max;
      p.earned_share = r.earned_share;
    } else if (r.has_points) {
      p.points = r.points;
    } else if (r.applied && r.cap) {
      // A cap that did not apply took nothing off, and there is nothing to show for it.
      if (!*r.applied) continue;
      p.cap = r.cap;
    } else {
      continue;
    }
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

Result<ClassAttempt> parseScoreReport(const std::string& text, const std::string& path, double file_time_s,
                                 const std::string& picture, const AttemptReadOptions& options) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Error{path + ": not a JSON object"};
  if (j.value("format", json()) != "dentsim-score") return Error{path + ": not a dentsim score report (no \"format\": \"dentsim-score\")"};
  auto report = ScoreReportSummary::fromJson(j);
  if (!report) return Error{path + ": " + report.message()};
  ClassAttempt a;
  a.source = path;
  a.verb = "scored";
  a.task = report->task_name;
  a.task_title = report->task_title.empty() ? a.task : report->task_title;
  a.task_kind = report->task_kind;
  a.score = report->total;
  a.pulp_exposed = report->pulp_exposed;
  a.adjacent_damaged = report->adjacent_damaged;
  a.guided = report->guided.has_value();
  // The student: the caller's, the report's own, the folders'.
  if (!options.student.empty()) a.student = options.student;
  else if (report->student) a.student = *report->student;
  else a.student = studentFromLayout(path);
  if (a.student.empty()) return Error{path + ": no student: give --student, a \"student\" field, or lay out STUDENT/ATTEMPT/score.json"};
  a.student_name = a.student;
  if (!report->timestamp) {
    a.time_s = file_time_s;
  } else {
    const auto t = parseIsoTime(*report->timestamp);
    if (!t) return Error{path + ": timestamp: not an ISO 8601 date and time"};
    a.time_s = *t;
  }
  a.statement_id = report->statement_id.value_or("");
  // What the page shows of why: the parts, the time taken, the surface agreement.
  a.total_max = report->total_max;
  a.parts = attemptPartsOf(report->parts);
  if (report->session) a.duration_s = report->session->elapsed_s;
  // No samples (no ideal surface to measure at) is no agreement, not 0 % of one.
  if (report->agreement && !(report->agreement->samples && *report->agreement->samples == 0))
    a.agreement = AttemptAgreement{report->agreement->band_mm, report->agreement->within_percent};
  a.picture = picture;
  return a;
}

// ---- 3. statements --------------------------------------------------------------------------------

namespace {

// The last segment of an IRI's path ("https://x/tasks/class2_cavity/" -> "class2_cavity").
std::string lastSegment(std::string iri) {
  if (const size_t cut = iri.find_first_of("?#"); cut != std::string::npos) iri.resize(cut);
  while (!iri.empty() && iri.back() == '/') iri.pop_back();
  const size_t slash = iri.find_last_of("/:");
  return slash == std::string::npos ? iri : iri.substr(slash + 1);
}

// The value at a path of keys; null when a step is missing or not an object.
const json* valueAt(const json& j, std::initializer_list<const char*> keys) {
  const json* at = &j;
  for (const char* k : keys) {
    if (!at->is_object()) return nullptr;
    const auto it = at->find(k);
    if (it == at->end()) return nullptr;
    at = &*it;
  }
  return at;
}

// The text at a path of keys when it is a string; empty otherwise.
std::string textAt(const json& j, std::initializer_list<const char*> keys) {
  const json* at = valueAt(j, keys);
  return at && at->is_string() ? at->get<std::string>() : "";
}

bool endsWith(const std::string& s, std::string_view tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// One statement; none when it carries no score. Errors are the problem alone; the caller names the line.
Result<std::optional<ClassAttempt>> parseStatement(const json& st, const std::string& folder, double file_time_s) {
  if (!st.is_object()) return Error{"not a JSON object"};
  const json result = st.value("result", json::object());
  if (!result.is_object()) return Error{"result: not an object"};
  const json score = result.value("score", json::object());
  if (!score.is_object()) return Error{"result.score: not an object"};
  const json raw = score.value("raw", json()), scaled = score.value("scaled", json());
  if (raw.is_null() && scaled.is_null()) return std::optional<ClassAttempt>{};
  ClassAttempt a;
  a.from_statement = true;
  if (!raw.is_null()) {
    if (!raw.is_number() || !(raw.get<double>() >= 0 && raw.get<double>() <= 100))
      return Error{"result.score.raw: not a number in [0, 100]"};
    a.score = raw.get<double>();
  } else {
    if (!scaled.is_number() || !(scaled.get<double>() >= 0 && scaled.get<double>() <= 1))
      return Error{"result.score.scaled: not a number in [0, 1]"};
    a.score = 100.0 * scaled.get<double>();
  }
  // The student: the account's name, else the display name, else the mailbox.
  const json actor = st.value("actor", json());
  if (!actor.is_object()) return Error{"actor: missing or not an object"};
  a.student = textAt(actor, {"account", "name"});
  if (a.student.empty()) a.student = textAt(actor, {"name"});
  if (a.student.empty()) a.student = textAt(actor, {"mbox"});
  if (a.student.empty()) return Error{"actor: no account.name, name or mbox"};
  a.student_name = textAt(actor, {"name"});
  if (a.student_name.empty()) a.student_name = a.student;
  // The task: the activity's last path segment, its English title.
  const std::string object_id = textAt(st, {"object", "id"});
  a.task = lastSegment(object_id);
  if (a.task.empty()) return Error{"object.id: missing or no task name in it"};
  // The title in English, else in the first language the statement gives, else the name.
  a.task_title = textAt(st, {"object", "definition", "name", "en-US"});
  if (a.task_title.empty()) {
    const json* names = valueAt(st, {"object", "definition", "name"});
    if (names && names->is_object())
      for (const auto& [lang, title] : names->items())
        if (title.is_string() && !title.get<std::string>().empty()) {
          a.task_title = title.get<std::string>();
          break;
        }
  }
  if (a.task_title.empty()) a.task_title = a.task;
  a.statement_id = textAt(st, {"id"});
  a.verb = lastSegment(textAt(st, {"verb", "id"}));
  if (a.verb.empty()) return Error{"verb.id: missing"};
  if (result.contains("success")) {
    if (!result["success"].is_boolean()) return Error{"result.success: not true or false"};
    a.success = result["success"].get<bool>();
  }
  if (result.contains("duration")) {
    const auto d = result["duration"].is_string() ? parseIsoDuration(result["duration"].get<std::string>()) : std::nullopt;
    if (!d) return Error{"result.duration: not an ISO 8601 duration"};
    a.duration_s = *d;
  }
  if (st.contains("timestamp")) {
    const auto t = st["timestamp"].is_string() ? parseIsoTime(st["timestamp"].get<std::string>()) : std::nullopt;
    if (!t) return Error{"timestamp: not an ISO 8601 date and time"};
    a.time_s = *t;
  } else {
    a.time_s = file_time_s;
  }
  // The extensions are keyed by IRI; only the name at the end matters here.
  const json ext = result.value("extensions", json::object());
  if (!ext.is_object()) return Error{"result.extensions: not an object"};
  for (const auto& [key, value] : ext.items()) {
    if (endsWith(key, "/pulp-exposed")) {
      if (!value.is_boolean()) return Error{"result.extensions " + key + ": not true or false"};
      a.pulp_exposed = value.get<bool>();
    } else if (endsWith(key, "/adjacent-damaged")) {
      if (!value.is_boolean()) return Error{"result.extensions " + key + ": not true or false"};
      a.adjacent_damaged = value.get<bool>();
    } else if (endsWith(key, "/guided")) {
      if (!value.is_boolean()) return Error{"result.extensions " + key + ": not true or false"};
      a.guided = value.get<bool>();
    } else if (endsWith(key, "/task-kind")) {
      if (!value.is_string()) return Error{"result.extensions " + key + ": not a task kind"};
      a.task_kind = value.get<std::string>();
    } else if (endsWith(key, "/total-max")) {
      a.total_max = numberAt(ext, key.c_str());
    } else if (endsWith(key, "/parts")) {
      if (value.is_object()) a.parts = readParts(value.value("components", json()), value.value("deductions", json()));
    } else if (endsWith(key, "/surface-agreement")) {
      a.agreement = agreementOf(value);
    } else if (endsWith(key, "/score-picture")) {
      if (!value.is_string()) return Error{"result.extensions " + key + ": not a path"};
      const fs::path p = value.get<std::string>();
      a.picture = p.empty() ? "" : (p.is_absolute() ? p : fs::path(folder) / p).string();
    }
  }
  return std::optional<ClassAttempt>{std::move(a)};
}

}  // namespace

Result<std::vector<ClassAttempt>> parseStatements(const std::string& text, const std::string& path, const std::string& folder,
                                             double file_time_s, int* skipped, std::vector<std::string>* warnings) {
  std::vector<ClassAttempt> attempts;
  std::string first_bad;  // the first bad line's "path:line: problem"
  bool any_good = false;  // a line that is a statement, scored or not
  forEachJsonLine(text, [&](int line, const std::string& row) {
    const std::string where = path + ":" + std::to_string(line);
    const json st = json::parse(row, nullptr, false);
    auto parsed = st.is_discarded() ? Result<std::optional<ClassAttempt>>(Error{"not a JSON statement (malformed JSON)"})
                                    : parseStatement(st, folder, file_time_s);
    // One bad line (a torn write, a hand edit) costs only itself: the rest of the class is reported.
    if (!parsed) {
      // Escaped: a path or a key from the file holding a newline or an ESC cannot break the one line.
      const std::string problem = shownPath(where + ": " + parsed.message());
      if (first_bad.empty()) first_bad = problem;
      if (warnings) warnings->push_back(problem + "; line left out");
      return;
    }
    any_good = true;
    if (!*parsed) {
      if (skipped) ++*skipped;
      return;
    }
    (*parsed)->source = where;
    attempts.push_back(std::move(**parsed));
  });
  // Not one statement in it: not an outbox at all (a damaged score report, a file given by mistake).
  if (!any_good && !first_bad.empty()) return Error{first_bad};
  return attempts;
}

// ---- 4. a whole file ------------------------------------------------------------------------------

Result<std::vector<ClassAttempt>> readAttempts(const std::string& path, const AttemptReadOptions& options, int* skipped,
                                                std::vector<std::string>* warnings) {
  if (!fs::is_regular_file(path)) return Error{path + ": no such file"};
  auto bytes = readFileBytes(path, kMaxInputBytes);
  if (!bytes) return bytes.error();
  const std::string text(bytes->begin(), bytes->end());
  const double mtime = fileTime(path);
  // A score report is one object naming its format; anything else is read as JSON lines, so that a
  // malformed outbox is reported by its line.
  const json whole = json::parse(text, nullptr, false);
  if (!whole.is_discarded() && whole.is_object() && whole.contains("format")) {
    const fs::path png = fs::path(path).parent_path() / "score.png";
    const std::string picture = fs::is_regular_file(png) ? png.string() : "";
    auto a = parseScoreReport(text, path, mtime, picture, options);
    if (!a) return a.error();
    return std::vector<ClassAttempt>{std::move(*a)};
  }
  const std::string folder = fs::path(path).parent_path().string();
  return parseStatements(text, path, folder.empty() ? "." : folder, mtime, skipped, warnings);
}

}  // namespace dentsim
