// Which tooth the simulator has loaded and from where: the built-in molar at a level, or a volume file (a course tooth, an embedded asset); chosen at the start, by the panel's tooth picker, or by a new task.
#pragma once

#include <string>

#include "core/result.h"
#include "eval/task_tooth.h"

namespace dentsim::app {

struct ToothChoice {
  std::string file;  // the tooth's volume file or asset; empty: the built-in molar
  int level = 0;     // the built-in molar's octree level; a file keeps its own grid, whatever this says

  bool builtin() const { return file.empty(); }
  // How the terminal and the panel name it.
  std::string name() const { return builtin() ? "built-in molar" : file; }

  // A task's tooth at the task's level (what the panel's task picker starts).
  static ToothChoice ofTask(const std::string& task_tooth, int task_level) {
    // Another built-in tooth goes by its session source ("builtin:molar_neighbours:9"), which
    // loadToothFileOrAsset builds and a session records as it is.
    if (isBuiltinTooth(task_tooth) && task_tooth != kBuiltinMolarTooth) return {builtinToothSource(task_tooth, task_level), task_level};
    return {task_tooth == kBuiltinMolarTooth ? std::string() : task_tooth, task_level};
  }

  // The run's first tooth: --tooth, else the task's; --level (0: not given) builds a built-in tooth
  // (the molar, or the molar with its neighbours) at that level, so with a file it is an error rather
  // than silently ignored.
  static Result<ToothChoice> atStart(const std::string& tooth_option, int level_option, const std::string& task_tooth,
                                     int task_level) {
    const bool other_builtin = tooth_option.empty() && isBuiltinTooth(task_tooth) && task_tooth != kBuiltinMolarTooth;
    if (other_builtin && level_option != 0) return ofTask(task_tooth, level_option);
    ToothChoice c = ofTask(task_tooth, task_level);
    if (!tooth_option.empty()) c.file = tooth_option;
    if (level_option != 0 && !c.builtin())
      return makeError("--level", "applies only to a built-in tooth; the tooth " + c.file + " keeps its own grid");
    if (level_option != 0) c.level = level_option;
    return c;
  }

  // The panel's tooth picker: a file, or the built-in molar at the picker's level. Picking a file
  // keeps the molar's level for when the molar is picked again without a level.
  ToothChoice picked(const std::string& picked_file, int picked_level) const {
    return {picked_file, picked_file.empty() ? picked_level : level};
  }
};

}  // namespace dentsim::app
