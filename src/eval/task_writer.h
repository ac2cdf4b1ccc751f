// The one writer of task files: a new task's keys as `dentsim task new` writes them, an ideal's object, and the checked, atomic write that `task new` and `task set-ideal` share.
//
// A task file is read back before it is written, so that dentsim never leaves a file that its own
// parser (eval/task.h) refuses.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/task.h"

namespace dentsim {

// The "ideal" object: "kind" and "path", then "final" and the hashes each when not empty.
nlohmann::ordered_json idealJson(const IdealSpec& ideal);

// The "crown" object with every key, in the order docs/SCORING.md lists them: a crown task's targets
// are the teacher's to read and change, so none is left to a default.
nlohmann::ordered_json crownJson(const CrownTask& crown);

// A version 2 task file of `task` with the keys a new task holds, in this order: format, version, name, kind, cavity_class (when not 0), title, instructions, tooth, level
// (the built-in molar only), tools (the mirror when named), target_s, failure_s (a kind with a
// failure time), force_error_n, pass_mark (when set), insertion_axis, leeway_mm, ideal (when set),
// from_ideal (when it lists any), view (when set) and crown (kind crown: crownJson). The score
// coefficients keep their defaults, so they are not written. The insertion axis is written as it
// stands, not normalized.
nlohmann::ordered_json newTaskJson(const Task& task);

// Writes `root` as the task file at `path` (2-space indent, a final newline), atomically, once it
// parses as a task; the task as read back. Errors: parseTask's, naming `path`, or the write's.
Result<Task> writeTaskFile(const std::string& path, const nlohmann::ordered_json& root);

}  // namespace dentsim
