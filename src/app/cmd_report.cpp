// `dentsim report SCORES_OR_OUTBOX... -o report.html` and `dentsim report --lrs URL`: one self-contained HTML page of a class's attempts, read from files or from the school's LRS (docs/CLASS_REPORT.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/learning_cli.h"
#include "core/text_escape.h"
#include "eval/attempt_reader.h"
#include "eval/class_report.h"
#include "eval/class_report_html.h"
#include "io/atomic_file.h"
#include "io/lrs_query.h"
#include "io/strict_json.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;

struct ReportCliOptions {
  std::vector<std::string> inputs;      // score reports, outboxes, or folders holding them
  std::string output = "report.html";
  std::string student;                  // the student of every score report given
  std::vector<std::string> pass_marks;  // "50" for every task, or "TASK=50"
  LearningCliOptions lrs;               // --lrs, --course, --config: the school's LRS, as `outbox send` reaches it
  std::string since;                    // --since: only statements the LRS stored after this date and time
  int lrs_page_size = 500;              // --lrs-page-size: statements per request to the LRS
};

// A score picture is a few hundred KiB; anything past this is not one.
constexpr uint64_t kMaxPictureBytes = 32ull << 20;

// The files a folder holds for the report: every score.json and every *.jsonl outbox, sorted so
// that the page does not depend on the order the file system lists them in.
std::vector<std::string> filesIn(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    const fs::path& p = it->path();
    if (p.filename() == "score.json" || p.extension() == ".jsonl") files.push_back(p.string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// "50" or "class2_cavity=50"; the error names the option's value.
Status parsePassMark(const std::string& text, ClassReportOptions* options) {
  const size_t eq = text.find('=');
  const std::string task = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::string value = eq == std::string::npos ? text : text.substr(eq + 1);
  double mark = 0.0;
  char tail = 0;
  if (std::sscanf(value.c_str(), "%lf%c", &mark, &tail) != 1 || !std::isfinite(mark) || mark < 0 || mark > 100 ||
      (eq != std::string::npos && task.empty()))
    return Error{"--pass-mark " + text + ": not a score in [0, 100] or TASK=SCORE"};
  if (task.empty()) options->pass_mark = mark;
  else options->task_pass_marks[task] = mark;
  return Ok{};
}

// What the page may embed of pictures, in PNG bytes (base64 makes it 4/3 of that on the page): a
// class's distinct pictures fit, while an outbox naming hundreds of large ones cannot make a page
// that a browser, or the memory building it, cannot hold. DENTSIM_REPORT_PICTURE_CAP_BYTES lowers
// it, for tests.
constexpr uint64_t kMaxEmbeddedPictureBytes = 64ull << 20;  // [B]

uint64_t embeddedPictureCap() {
  const char* text = std::getenv("DENTSIM_REPORT_PICTURE_CAP_BYTES");
  char* end = nullptr;
  const unsigned long long cap = text && *text ? std::strtoull(text, &end, 10) : 0;
  return (end && *end == '\0' && cap > 0) ? uint64_t(cap) : kMaxEmbeddedPictureBytes;
}

// Every picture the attempts name, in the page's order: embedded while the cap allows (a copy of
// one already embedded costs nothing), linked by its path past it, with one warning. One that
// cannot be read is a warning: the attempt still counts, and its place on the page says "no picture".
ReportPictures loadPictures(const std::vector<ClassAttempt>& attempts, uint64_t cap) {
  static constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  ReportPictures pictures;
  std::set<std::string> tried;
  uint64_t embedded_bytes = 0;
  for (const ClassAttempt& a : attempts) {
    if (a.picture.empty() || !tried.insert(a.picture).second) continue;
    auto bytes = readFileBytes(a.picture, kMaxPictureBytes);
    if (!bytes) {
      warn(bytes.message() + " (the picture of " + a.source + "); shown as no picture");
      continue;
    }
    if (bytes->size() < 8 || !std::equal(kPngSignature, kPngSignature + 8, bytes->begin())) {
      warn(a.picture + ": not a PNG (the picture of " + a.source + "); shown as no picture");
      continue;
    }
    const bool copy = std::find(pictures.pngs.begin(), pictures.pngs.end(), *bytes) != pictures.pngs.end();
    if (!copy && embedded_bytes + bytes->size() > cap) {
      pictures.linked.insert(a.picture);
      continue;
    }
    if (pictures.add(a.picture, std::move(*bytes))) embedded_bytes += pictures.pngs.back().size();
  }
  if (!pictures.linked.empty())
    warnf("%zu picture(s) past the %llu bytes of pictures a page embeds are linked by their path instead (the first: %s)",
          pictures.linked.size(), static_cast<unsigned long long>(cap), shownPath(*pictures.linked.begin()).c_str());
  return pictures;
}

// At most this many warnings for one input's bad lines; a file of nothing else says so once.
constexpr size_t kMaxLineWarningsPerFile = 10;

// --since as the LRS wants it: a date ("2026-11-27", midnight UTC) or an ISO 8601 date and time.
Result<std::string> sinceTimestamp(const std::string& text) {
  const bool date_only = text.size() == 10 && text[4] == '-' && text[7] == '-';
  const auto seconds = parseIsoTime(date_only ? text + "T00:00:00Z" : text);
  if (!seconds) return Error{"--since " + quotedForMessage(text) + ": not a date (2026-11-27) or an ISO 8601 date and time"};
  return xapiTimestamp(*seconds);
}

// The course's statements from the school's LRS (io/lrs_query.h), read as an outbox's lines are:
// each one's source is "LRS <url>:<n>", the n-th statement read, oldest stored first.
Status readFromLrs(const ReportCliOptions& o, std::vector<ClassAttempt>* attempts, int* skipped) {
  auto settings = lrsForReading(o.lrs);
  if (!settings) return settings.error();
  StatementQuery query;
  query.activity = settings->course_activity;
  query.related_activities = true;  // a task's statement names its course as its parent, not as its object
  query.page_limit = o.lrs_page_size;
  if (!o.since.empty()) {
    auto since = sinceTimestamp(o.since);
    if (!since) return since.error();
    query.since = *since;
  }
  auto fetched = fetchStatements(settings->lrs, query);
  if (!fetched) return fetched.error();
  // None: the caller's one error line says there is nothing to report.
  if (fetched->statements.empty()) return Ok{};
  const std::string where = "LRS " + urlForMessage(settings->lrs.url);
  std::printf("read %zu statement(s) of course %s from %s in %d request(s)\n", fetched->statements.size(), settings->course.c_str(),
              where.c_str(), fetched->requests);
  // One statement a line, as an outbox holds them, so that both sources are read by the same rules.
  std::string lines;
  for (const nlohmann::ordered_json& statement : fetched->statements)
    lines += statement.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  std::vector<std::string> warnings;
  auto read = parseStatements(lines, where, ".", 0.0, skipped, &warnings);
  if (!read) return read.error();
  for (size_t i = 0; i < warnings.size() && i < kMaxLineWarningsPerFile; ++i) warn(warnings[i]);
  if (warnings.size() > kMaxLineWarningsPerFile)
    warn(where + ": " + std::to_string(warnings.size() - kMaxLineWarningsPerFile) + " more bad statements left out");
  attempts->insert(attempts->end(), read->begin(), read->end());
  return Ok{};
}

int runReport(const ReportCliOptions& o) {
  if (o.inputs.empty() && o.lrs.lrs.empty()) return fail("report: give score reports, outboxes or folders, or --lrs URL");
  ClassReportOptions report_options;
  for (const std::string& p : o.pass_marks)
    if (Status st = parsePassMark(p, &report_options); !st) return fail(st.message());
  // Folders expand to their files; every file is read before anything is written.
  std::vector<std::string> files;
  for (const std::string& in : o.inputs) {
    if (fs::is_directory(in)) {
      const std::vector<std::string> found = filesIn(in);
      if (found.empty()) return fail(in + ": no score.json or .jsonl outbox in this folder");
      files.insert(files.end(), found.begin(), found.end());
    } else {
      files.push_back(in);
    }
  }
  if (Status st = checkOutputsAreNotInputs(files, {o.output}); !st) return fail(st.message());
  AttemptReadOptions read_options;
  read_options.student = o.student;
  std::vector<ClassAttempt> attempts;
  int skipped = 0;
  for (const std::string& f : files) {
    std::vector<std::string> warnings;
    auto read = readAttempts(f, read_options, &skipped, &warnings);
    if (!read) return fail(read.message());
    // A bad line costs itself, and says so: the rest of the class is reported.
    for (size_t i = 0; i < warnings.size() && i < kMaxLineWarningsPerFile; ++i)
      warn(warnings[i]);
    if (warnings.size() > kMaxLineWarningsPerFile)
      warn(shownPath(f) + ": " + std::to_string(warnings.size() - kMaxLineWarningsPerFile) + " more bad lines left out");
    attempts.insert(attempts.end(), read->begin(), read->end());
  }
  if (!o.lrs.lrs.empty())
    if (Status st = readFromLrs(o, &attempts, &skipped); !st) return fail(st.message());
  if (attempts.empty())
    return fail(o.lrs.lrs.empty() ? "no scored attempt in " + std::to_string(files.size()) + " input files"
                                  : "no scored attempt in the input files or the LRS's statements");
  const ClassReport report = buildClassReport(std::move(attempts), report_options);
  // The pictures the page embeds are inputs too: a page written over one would destroy it.
  std::vector<std::string> picture_files;
  for (const ClassAttempt& a : report.attempts) picture_files.push_back(a.picture);
  if (Status st = checkOutputsAreNotInputs(picture_files, {o.output}); !st) return fail(st.message());
  const ReportPictures pictures = loadPictures(report.attempts, embeddedPictureCap());
  if (Status st = writeFileAtomic(o.output, classReportHtml(report, pictures)); !st) return fail(st.message());
  std::printf("wrote %s: %zu attempts by %zu students at %zu tasks, %zu to look at, %zu pictures", o.output.c_str(),
              report.attempts.size(), report.students.size(), report.tasks.size(), report.flags.size(), pictures.count());
  if (skipped > 0) std::printf(" (%d statements without a score left out)", skipped);
  if (report.duplicates > 0) std::printf(" (%d statements or score reports given twice counted once)", report.duplicates);
  if (report.merged > 0) std::printf(" (%d score reports and their statements counted once)", report.merged);
  std::printf("\n");
  return 0;
}

}  // namespace

void addReportCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<ReportCliOptions>();
  CLI::App* cmd = root.add_subcommand("report", "A class's score reports and xAPI outboxes as one self-contained HTML page");
  cmd->add_option("inputs", o->inputs,
                  "score.json files, outboxes of xAPI statements (JSON lines), or folders holding them (their score.json and *.jsonl)");
  cmd->add_option("-o,--output", o->output, "Page to write (.html)")->capture_default_str();
  cmd->add_option("--student", o->student,
                  "The student of every score report given (default: the report's \"student\", else the folder two above it: STUDENT/ATTEMPT/score.json)");
  // One value per --pass-mark, so that the inputs after it stay inputs.
  cmd->add_option("--pass-mark", o->pass_marks, "A pass mark of 100 for every task (50), or for one task (class2_cavity=60); repeatable")
      ->allow_extra_args(false);
  // The school's LRS as a source: the same settings and credentials as `outbox send`.
  CLI::Option* lrs = cmd->add_option("--lrs", o->lrs.lrs, "Read the course's statements from this LRS's xAPI endpoint (credentials: config or DENTSIM_LRS_USERNAME/PASSWORD)");
  cmd->add_option("--course", o->lrs.course, "With --lrs: the course id (default: the config's, else builtin)")->needs(lrs);
  cmd->add_option("--config", o->lrs.config, "With --lrs: the learning-record config file (default: $DENTSIM_CONFIG, else ~/.config/dentsim/learning.json)")->needs(lrs);
  cmd->add_option("--since", o->since, "With --lrs: only statements the LRS stored after this date (2026-11-27) or date and time (UTC unless a zone is given)")->needs(lrs);
  cmd->add_option("--lrs-page-size", o->lrs_page_size, "With --lrs: statements per request")
      ->check(CLI::Range(1, kMaxStatementPageLimit))
      ->needs(lrs)
      ->capture_default_str();
  cmd->callback([o, &action] { action = [o] { return runReport(*o); }; });
}

}  // namespace dentsim::app
