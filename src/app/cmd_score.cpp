// `dentsim score --task caries|cavity --initial A.dvol --final B.dvol [--ideal C.dvol] [--session S]`: the score report (JSON) of a cut, and its pictures (PNG) when asked.
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
  std::string png;             // the score picture; none when empty
  std::string deviation_png;   // the deviation picture of a cavity or access; none when empty
  bool json = false;
  LearningCliOptions learning;  // the attempt's learning record, when a student is named
};

int runScore(const ScoreCliOptions& o) {
  // The student's name and the config first: a name refused after the scoring wasted it.
  if (Status st = checkLearningOptions(o.learning); !st) return fail(st.message());
  if (Status st = checkOutputsAreNotInputs({o.initial, o.final_, o.ideal, o.session, o.task}, {o.report, o.png, o.deviation_png});
      !st)
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
    if (!read->truncation_warning.empty()) warn(read->truncation_warning);
    session = std::move(*read);
  }
  ScoreFiles files = scoreFiles(o.initial, o.final_, o.session);
  files.ideal = o.ideal;
  auto score = scoreCut(*task, *initial, *final_, ideal ? &*ideal : nullptr, session ? &*session : nullptr, files);
  if (!score) return fail(score.message());
  // Before anything is written: a caries removal, or a crown without an ideal, has no ideal surface to draw.
  if (!o.deviation_png.empty() && !score->agreement)
    return fail("--deviation-png: task " + task->name +
                (task->kind == TaskKind::Crown
                     ? " is a crown preparation without an ideal; the deviation picture needs one (the task's or --ideal)"
                     : " is a caries removal; the deviation picture needs a cavity or access task, which has an ideal cavity"));
  // Recorded before the report is written, so that the report names its statement and a class report
  // counts the attempt once; the record's own failures are a warning, the score stands.
  recordAttemptOrWarn(o.learning, *task, score->report, o.session, o.final_);
  if (Status st = writeScoreReport(o.report, score->report); !st) return fail(st.message());
  for (const std::string& w : score->warnings) warn(w);
  std::string wrote = o.report;
  if (!o.png.empty()) {
    if (Status st = writeScoreImage(o.png, *task, *initial, *final_, *score, ideal ? &*ideal : nullptr); !st)
      return fail(st.message());
    wrote += (o.deviation_png.empty() ? " and " : ", ") + o.png;
  }
  if (!o.deviation_png.empty()) {
    if (Status st = writeDeviationImage(o.deviation_png, *task, *initial, *score, ideal ? &*ideal : nullptr); !st)
      return fail(st.message());
    wrote += " and " + o.deviation_png;
  }
  // Sent before the report is printed, so that --json's report stays the last thing on stdout.
  if (Status st = sendPendingIfConfigured(o.learning); !st) return fail(st.message());
  if (o.json)
    std::printf("%s\n", score->report.dump(2).c_str());
  else
    std::printf("%s\nwrote %s\n", score->summary.c_str(), wrote.c_str());
  return 0;
}

}  // namespace

void addScoreCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<ScoreCliOptions>();
  CLI::App* cmd = root.add_subcommand("score", "Score a cut tooth against the start (and the ideal): JSON report, and PNG pictures when asked");
  cmd->add_option("--task", o->task, "caries, cavity, a built-in task by name (class2_cavity, class5_cavity, access_cavity, ...), or a task file (.json)")->required();
  cmd->add_option("--initial", o->initial, "The tooth before the cut (.dvol)")->required();
  cmd->add_option("--final", o->final_, "The tooth after the cut (.dvol)")->required();
  cmd->add_option("--ideal", o->ideal, "The professional's final tooth (.dvol); default: the task's ideal");
  cmd->add_option("--session", o->session, "The session (.dses), for time, force and bur-angle statistics");
  cmd->add_option("-o,--report", o->report, "Report to write (.json)")->capture_default_str();
  cmd->add_option("--png", o->png,
                  "Score picture to write: over-cut red, under-cut blue; a crown: its reduction map, finish line and "
                  "undercut (.png); none unless given");
  cmd->add_option("--deviation-png", o->deviation_png,
                  "Cavity, access and a crown with an ideal: deviation picture to write: the ideal's cut surface green within the "
                  "+/-0.2 mm band, red where cut beyond it, blue where short of it (.png)");
  cmd->add_flag("--json", o->json, "Print the report on stdout");
  addLearningOptions(cmd, o->learning);
  cmd->callback([o, &action] { action = [o] { return runScore(*o); }; });
}

}  // namespace dentsim::app
