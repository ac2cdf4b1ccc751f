// `dentsim task validate TASK.json [--out DIR]`: every scripted attempt derived from the task's professional drilled headless, scored, and checked, so a task proves its own score before a student meets it.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "eval/cut_score.h"
#include "eval/task_tooth.h"
#include "eval/task_validation.h"
#include "io/atomic_file.h"
#include "sim/builtin_tooth.h"
#include "volume/brick_layout.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;

struct TaskValidateOptions {
  std::string task;                    // a task file or a built-in task's name
  std::string out;                     // validation.json and validation.md; empty: print only
  int level = 0;                       // the built-in molar's level; 0: the task's
  std::vector<std::string> attempts;   // empty: all
  bool pictures = false;               // each attempt's score picture into out/
};

int runTaskValidate(const TaskValidateOptions& o) {
  auto task = builtinTask(o.task);
  if (!task) return fail(task.message());
  if (o.level != 0 && !isBuiltinTooth(task->tooth))
    return fail("--level applies to a task on the built-in molar; " + task->tooth + " keeps its own grid");
  if (o.level != 0 && task->ideal && task->ideal->kind != IdealKind::BuiltinPath)
    return fail("--level: the task's ideal was recorded on the molar at its own level; validate it at that level");
  if (o.pictures && o.out.empty()) return fail("--pictures needs --out");
  ValidationSettings settings;
  if (!o.attempts.empty()) {
    auto attempts = parseAttemptList(o.attempts, "--attempts");
    if (!attempts) return fail(attempts.message());
    settings.attempts = std::move(*attempts);
  }
  // The shipped tasks' times were set from their professional drilled at the task's level; drilled at
  // another, the professional's pace differs, so its times are set again from this run's, by the same rule.
  if (o.level != 0 && o.level != task->level) {
    settings.time_from_professional = true;
    std::fprintf(stderr, "  level %d instead of the task's %d: the times are set from the professional drilled at it\n", o.level,
                 task->level);
  }
  auto tooth = taskTooth(*task, o.level);
  if (!tooth) return fail(tooth.message());
  std::error_code ec;
  if (!o.out.empty()) {
    fs::create_directories(o.out, ec);
    if (ec) return fail(o.out + ": cannot make the folder: " + ec.message());
    if (o.pictures) settings.picture_dir = o.out;
  }
  std::string work = (fs::temp_directory_path(ec) / "dentsim-validate-XXXXXX").string();
  if (!::mkdtemp(work.data())) return fail(work + ": cannot make a folder for the attempts' sessions");
  settings.work_dir = work;
  auto v = validateTask(*task, *tooth, settings, [](const std::string& step) { std::fprintf(stderr, "  %s\n", step.c_str()); });
  fs::remove_all(work, ec);
  if (!v) return fail(v.message());
  const std::string md = validationMarkdown(*v);
  if (!o.out.empty()) {
    const std::string json_path = (fs::path(o.out) / "validation.json").string();
    const std::string md_path = (fs::path(o.out) / "validation.md").string();
    if (Status st = writeFileAtomic(json_path, validationJson(*v).dump(2) + "\n"); !st) return fail(st.message());
    if (Status st = writeFileAtomic(md_path, md); !st) return fail(st.message());
  }
  std::fputs(md.c_str(), stdout);
  for (const std::string& f : v->failures) std::fprintf(stderr, "dentsim: %s: %s\n", task->name.c_str(), f.c_str());
  if (!v->valid()) return 1;
  std::printf("%s: valid\n", task->name.c_str());
  return 0;
}

}  // namespace

void addTaskValidateCommand(CLI::App& task_cmd, Action& action) {
  auto o = std::make_shared<TaskValidateOptions>();
  CLI::App* cmd = task_cmd.add_subcommand(
      "validate", "Drill every scripted attempt derived from the task's professional, score each, and check the score tells them apart");
  cmd->add_option("task", o->task, "The task file, or a built-in task's name")->required();
  cmd->add_option("--out", o->out, "Folder for validation.json and validation.md");
  cmd->add_option("--level", o->level, "A task on the built-in molar: drill it at this level instead of the task's")
      ->check(CLI::Range(DS_MIN_LEVEL, DS_MAX_LEVEL));
  cmd->add_option("--attempts", o->attempts, "Only these attempts (the expert always runs): " + attemptNames() + "; at a crown: " + crownAttemptNames())->delimiter(',');
  cmd->add_flag("--pictures", o->pictures, "Also each attempt's score picture, into --out");
  cmd->callback([o, &action] { action = [o] { return runTaskValidate(*o); }; });
}

}  // namespace dentsim::app
