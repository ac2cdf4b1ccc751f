// The score benchmark (`dentsim bench scores`): `task validate`'s scripted attempts at every built-in task on the molar, scored, in one table, JSON and bar chart.
//
// Construct validity, measured: every attempt that eval/task_validation.h derives from a task's
// professional (a second careful hand and one attempt per fault) is drilled by the scripted pen on
// the same tooth, recorded, and scored through eval's scoreCut like any student's, and checked as
// `task validate` checks it. Scripted attempts are deterministic, so a second run gives the same
// scores to the last bit. Drilled at another level than a task's own, its times are set from the
// professional drilled at that level, by set-ideal's rule (eval/task_ideal.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/task.h"
#include "eval/task_validation.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

struct ScoreBenchResult {
  int level = 0;
  double voxel_mm = 0.0;
  std::vector<TaskValidation> tasks;  // each task's attempts and checks, in the order given
};

// Runs `task validate`'s attempts at each task on `molar` (the built-in molar at some level).
// `progress` is told each step as it starts (may be empty). Errors: a task with no professional to
// derive from, or a failed run.
Result<ScoreBenchResult> runScoreBench(const ToothVolume& molar, const std::vector<Task>& tasks,
                                       const ValidationSettings& settings,
                                       const std::function<void(const std::string&)>& progress = {});

// Every check that failed, over all tasks: "<task>: <the check's line>".
std::vector<std::string> scoreBenchFailures(const ScoreBenchResult& result);

nlohmann::ordered_json scoreBenchJson(const ScoreBenchResult& result);
std::string scoreBenchMarkdown(const ScoreBenchResult& result);
std::string scoreBenchSvg(const ScoreBenchResult& result);

}  // namespace dentsim::bench
