// `dentsim score --task caries|cavity --initial A.dvol --final B.dvol [--ideal C.dvol] [--session S]`: the score report (JSON) and picture (PNG) of a cut.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/learning_cli.h"
#include "eval/cut_score.h"
#include "io/session_file.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct ScoreCliOptions {
  std::string task;            // caries, cavity, or a task file
  std::string initial, final_, ideal, session;
  std::string report = "score.json";
  std::string png = "score.png";
  bool json = false;
  LearningCliOptions learning;  // the attempt's learning record, when a student is named
};

int runScore(const ScoreCliOptions& o) {
  if (Status st = checkOutputsAreNotInputs({o.initial, o.final_, o.ideal, o.session, o.task}, {o.report, o.png}); !st)
    return fail(st.message());
  auto task = builtinTask(o.task);
  if (!task) return fail(task.message());
  auto initial = loadTooth(o.initial);
  if (!initial) return fail(initial.message());
  auto final_ = loadTooth(o.final_);
  if (!final_) return fail(final_.message());
  std::optional<ToothVolume> ideal;
  if (!o.ideal.empty()) {
    auto loaded = loadTooth(o.ideal);
    if (!loaded) return fail(loaded.message());
    ideal = std::move(*loaded);
  }
  std::optional<SessionRecording> session;
  if (!o.session.empty()) {
    auto read = readSessionFile(o.session);
    if (!read) return fail(read.message());
    if (!read->truncation_warning.empty()) std::fprintf(stderr, "dentsim: warning: %s\n", read->truncation_warning.c_str());
    session = std::move(*read);
  }
  ScoreFiles files = scoreFiles(o.initial, o.final_, o.session);
  files.ideal = o.ideal;
  auto score = scoreCut(*task, *initial, *final_, ideal ? &*ideal : nullptr, session ? &*session : nullptr, files);
  if (!score) return fail(score.message());
  if (Status st = writeScoreReport(o.report, score->report); !st) return fail(st.message());
  for (const std::string& w : score->warnings) std::fprintf(stderr, "dentsim: warning: %s\n", w.c_str());
  if (Status st = writeScoreImage(o.png, *task, *initial, *final_, *score, ideal ? &*ideal : nullptr); !st)
    return fail(st.message());
  // The learning record before the report, so that --json's report stays the last thing printed.
  if (Status st = recordAttempt(o.learning, *task, score->report, o.session, o.final_); !st) return fail(st.message());
  if (Status st = sendPendingIfConfigured(o.learning); !st) return fail(st.message());
  if (o.json)
    std::printf("%s\n", score->report.dump(2).c_str());
  else
    std::printf("%s\nwrote %s and %s\n", score->summary.c_str(), o.report.c_str(), o.png.c_str());
  return 0;
}

}  // namespace

void addScoreCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<ScoreCliOptions>();
  CLI::App* cmd = root.add_subcommand("score", "Score a cut tooth against the start (and the ideal): JSON report and PNG");
  cmd->add_option("--task", o->task, "caries, cavity, a built-in task by name (class2_cavity, class5_cavity, access_cavity, ...), or a task file (.json)")->required();
  cmd->add_option("--initial", o->initial, "The tooth before the cut (.dvol)")->required();
  cmd->add_option("--final", o->final_, "The tooth after the cut (.dvol)")->required();
  cmd->add_option("--ideal", o->ideal, "The professional's final tooth (.dvol); default: the task's ideal");
  cmd->add_option("--session", o->session, "The session (.dses), for time, force and bur-angle statistics");
  cmd->add_option("-o,--report", o->report, "Report to write (.json)")->capture_default_str();
  cmd->add_option("--png", o->png, "Picture to write: over-cut red, under-cut blue (.png)")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the report on stdout");
  addLearningOptions(cmd, o->learning);
  cmd->callback([o, &action] { action = [o] { return runScore(*o); }; });
}

}  // namespace dentsim::app
