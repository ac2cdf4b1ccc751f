// `dentsim bench scores [--level 8] [--tasks A,B] [--out DIR]`: task validate's attempts at every built-in task on the molar, scored, as a table, JSON and a bar chart.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/commands.h"
#include "bench/score_bench.h"
#include "eval/cut_score.h"
#include "eval/task_tooth.h"
#include "io/atomic_file.h"
#include "sim/builtin_tooth.h"

namespace dentsim::app {
namespace {

struct ScoresBenchOptions {
  int level = 8;                       // octree level of the built-in molar
  std::vector<std::string> attempts;   // empty: all
  std::vector<std::string> tasks;      // built-in task names; empty: every one on the built-in molar
  std::string out = "docs/bench";      // scores.json, scores.md, scores.svg
  bool pictures = false;               // also each attempt's score picture, into out/scores/
};

int runScoresBench(const ScoresBenchOptions& o) {
  namespace fs = std::filesystem;
  ValidationSettings settings;
  if (!o.attempts.empty()) {
    auto attempts = parseAttemptList(o.attempts, "--attempts");
    if (!attempts) return fail(attempts.message());
    settings.attempts = std::move(*attempts);
  }
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create the output folder: " + ec.message());
  // The sessions go to a private folder under the system's temporary one, removed at the end.
  const fs::path work = fs::temp_directory_path(ec) / ("dentsim-bench-scores-" + std::to_string(::getpid()));
  fs::create_directories(work, ec);
  if (ec) return fail(work.string() + ": cannot create a working folder: " + ec.message());
  settings.work_dir = work.string();
  if (o.pictures) {
    settings.picture_dir = (fs::path(o.out) / "scores").string();
    fs::create_directories(settings.picture_dir, ec);
    if (ec) return fail(settings.picture_dir + ": cannot create: " + ec.message());
  }

  auto molar = builtinMolarTooth(o.level);
  if (!molar) return fail(molar.message());
  // Every shipped task on the built-in molar (assets/tasks/*.json), or those named.
  std::vector<Task> tasks;
  for (const std::string& name : o.tasks.empty() ? builtinTaskNames() : o.tasks) {
    auto task = builtinTask(name);
    if (!task) return fail("--tasks: " + task.message());
    if (task->tooth != kBuiltinMolarTooth) {
      if (!o.tasks.empty()) return fail("--tasks: " + name + " is not on the built-in molar");
      continue;
    }
    tasks.push_back(std::move(*task));
  }
  std::printf("scores bench: %zu tasks on the built-in molar at level %d (%.4f mm voxels)\n", tasks.size(), o.level,
              molar->frame.voxel_mm);
  auto result = bench::runScoreBench(*molar, tasks, settings, [](const std::string& line) {
    std::printf("  %s\n", line.c_str());
    std::fflush(stdout);
  });
  fs::remove_all(work, ec);
  if (!result) return fail(result.message());

  const std::string markdown = bench::scoreBenchMarkdown(*result);
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"scores.json", bench::scoreBenchJson(*result).dump(2) + "\n"},
                                   {"scores.md", markdown},
                                   {"scores.svg", bench::scoreBenchSvg(*result)}})
    if (Status st = writeFileAtomic((fs::path(o.out) / name).string(), text); !st) return fail(st.message());
  std::printf("\n%s", markdown.c_str());
  const std::vector<std::string> failures = bench::scoreBenchFailures(*result);
  for (const std::string& f : failures) std::printf("check: %s\n", f.c_str());
  std::printf("%s\nwrote %s/scores.json, scores.md, scores.svg%s\n",
              failures.empty() ? "every task is valid: each fault loses at least 20 points against the expert, most in its own part"
                               : "some tasks are not valid (above)",
              o.out.c_str(), o.pictures ? " and scores/*.png" : "");
  return 0;
}

}  // namespace

void addScoresBenchCommand(CLI::App& bench, Action& action) {
  auto o = std::make_shared<ScoresBenchOptions>();
  CLI::App* cmd = bench.add_subcommand("scores", "task validate's scripted attempts (a second expert, over-cut, under-cut, heavy, slow, "
                                                 "trench, tilted, token) at every built-in task on the molar, scored: the gaps");
  cmd->add_option("--level", o->level, "Octree level of the molar")->check(CLI::Range(6, 10))->capture_default_str();
  cmd->add_option("--attempts", o->attempts, "Attempts to run besides the expert: " + attemptNames() + "; at a crown: " + crownAttemptNames())->delimiter(',');
  cmd->add_option("--tasks", o->tasks, "Built-in tasks to run (default: every one on the built-in molar: " +
                                          [] {
                                            std::string list;
                                            for (const std::string& n : builtinTaskNames()) list += (list.empty() ? "" : ", ") + n;
                                            return list;
                                          }() + ")")
      ->delimiter(',');
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_flag("--pictures", o->pictures, "Also write each attempt's score picture to OUT/scores/");
  cmd->callback([o, &action] { action = [o] { return runScoresBench(*o); }; });
}

}  // namespace dentsim::app
