// The checks of a task definition beyond its schema (`dentsim task check`): the tools in the catalog (a crown's bur for its finish), the tooth holding what the kind needs, a valid axis, an ideal that cuts.
//
// parseTask (eval/task.h) already holds a task file to its schema: keys, types, ranges and times.
// These checks need what a file cannot say of itself: the tool catalog, the tooth and the ideal.
#pragma once

#include <string>
#include <vector>

#include "eval/task.h"
#include "eval/task_kinds.h"
#include "volume/brick_volume.h"

namespace dentsim {

// What is wrong with a task, each a line "<key>: <problem>" in the order the checks ran. An error
// makes the task unusable; a warning is worth the teacher's look.
struct TaskProblems {
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
  bool ok() const { return errors.empty(); }
};

// Whether a tooth of these totals lacks the tissue the kind needs (kind.required_tissue): a caries
// removal without caries, an access without a pulp. False for a kind that needs none.
bool lacksRequiredTissue(const TaskKindRow& kind, const MaterialTotals& totals);

// Checks a task as builtinTask (eval/cut_score.h) reads it, its files resolved: the drill is a bur
// and the mirror a mirror of the tool catalog (a crown's drill not of its finish line is a warning,
// eval/crown_targets.h); the tooth loads and holds the kind's tissue; the
// insertion axis suits the kind and class on it (eval/task_axis.h); the ideal is made, and cuts
// (a warning when it cut an adjacent tooth: the professional is to leave neighbours whole).
// Loads the tooth and makes the ideal: a built-in path is drilled, a session replayed.
TaskProblems checkTask(const Task& task);

}  // namespace dentsim
