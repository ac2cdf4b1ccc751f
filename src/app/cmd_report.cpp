// `dentsim report SCORES_OR_OUTBOX... -o report.html`: one self-contained HTML page of a class's attempts (docs/CLASS_REPORT.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "eval/attempt_reader.h"
#include "eval/class_report.h"
#include "eval/class_report_html.h"
#include "io/atomic_file.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;

struct ReportCliOptions {
  std::vector<std::string> inputs;      // score reports, outboxes, or folders holding them
  std::string output = "report.html";
  std::string student;                  // the student of every score report given
  std::vector<std::string> pass_marks;  // "50" for every task, or "TASK=50"
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

// The PNG bytes of every picture the attempts name. One that cannot be read is a warning: the
// attempt still counts, and its place on the page says "no picture".
ReportPictures loadPictures(const std::vector<ClassAttempt>& attempts) {
  static constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  ReportPictures pictures;
  for (const ClassAttempt& a : attempts) {
    if (a.picture.empty() || pictures.count(a.picture)) continue;
    auto bytes = readFileBytes(a.picture, kMaxPictureBytes);
    if (!bytes) {
      std::fprintf(stderr, "dentsim: warning: %s (the picture of %s); shown as no picture\n", bytes.message().c_str(), a.source.c_str());
      continue;
    }
    if (bytes->size() < 8 || !std::equal(kPngSignature, kPngSignature + 8, bytes->begin())) {
      std::fprintf(stderr, "dentsim: warning: %s: not a PNG (the picture of %s); shown as no picture\n", a.picture.c_str(), a.source.c_str());
      continue;
    }
    pictures.emplace(a.picture, std::move(*bytes));
  }
  return pictures;
}

int runReport(const ReportCliOptions& o) {
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
    auto read = readAttempts(f, read_options, &skipped);
    if (!read) return fail(read.message());
    attempts.insert(attempts.end(), read->begin(), read->end());
  }
  if (attempts.empty()) return fail("no scored attempt in " + std::to_string(files.size()) + " input files");
  const ReportPictures pictures = loadPictures(attempts);
  const ClassReport report = buildClassReport(std::move(attempts), report_options);
  if (Status st = writeFileAtomic(o.output, classReportHtml(report, pictures)); !st) return fail(st.message());
  std::printf("wrote %s: %zu attempts by %zu students at %zu tasks, %zu to look at, %zu pictures", o.output.c_str(),
              report.attempts.size(), report.students.size(), report.tasks.size(), report.flags.size(), pictures.size());
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
                  "score.json files, outboxes of xAPI statements (JSON lines), or folders holding them (their score.json and *.jsonl)")
      ->required();
  cmd->add_option("-o,--output", o->output, "Page to write (.html)")->capture_default_str();
  cmd->add_option("--student", o->student,
                  "The student of every score report given (default: the report's \"student\", else the folder two above it: STUDENT/ATTEMPT/score.json)");
  // One value per --pass-mark, so that the inputs after it stay inputs.
  cmd->add_option("--pass-mark", o->pass_marks, "A pass mark of 100 for every task (50), or for one task (class2_cavity=60); repeatable")
      ->allow_extra_args(false);
  cmd->callback([o, &action] { action = [o] { return runReport(*o); }; });
}

}  // namespace dentsim::app
