// The tooth and task pickers' lists: the built-in molar at its levels and the built-in tasks, then a course folder's tooth (.dvol) and task (.json) files, each task with its title and instructions or the error that keeps it from loading.
//
// The panel shows these lists and the app restarts on what is picked (docs/SIMULATOR.md, "Teeth and
// tasks"). Listing never fails as a whole: a file that does not load is listed with its error, so
// the teacher sees which file is broken and why, and a folder that cannot be read says so once.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace dentsim::ui {

inline constexpr int kMinLevel = 7;   // the coarsest built-in molar the panel offers
inline constexpr int kMaxLevel = 10;  // the paper's finest

// One tooth the simulator can restart on.
struct ToothChoice {
  std::string label;  // the picker's line: "built-in molar, level 9", "tooth_2.dvol", "molar.dvol (synthesized layers)"
  std::string path;   // the volume file; empty: the built-in molar
  int level = 0;      // the built-in molar's octree level, kMinLevel..kMaxLevel; 0 for a file
};

// One task the simulator can start.
struct TaskChoice {
  std::string source;        // what eval's builtinTask takes: a built-in task's name or a task file's path
  std::string label;         // the picker's line: a built-in task's name ("class1_cavity"), a file's name ("class1_cavity.json")
  std::string title;         // the task's one-line title; empty when it does not load
  std::string instructions;  // what the student is to do; empty when the task has none or does not load
  bool builtin = false;      // embedded in dentsim, not a file: it cannot take a recorded ideal
  std::string error;         // why it does not load; empty when it does
  std::string name{};        // the task's own name (its learning records' activity); empty when it does not load
  std::optional<double> pass_mark{};  // the task's pass mark [points of 100]; none: it has none
  // The student's own record at it (filled by the app from the outbox, eval/student_records.h).
  int attempts = 0;                 // scored attempts
  std::optional<double> best{};     // the best total [points of 100]; none without attempts
  bool passed = false;              // the best reaches the pass mark (eval/student_records.h taskPassed)
};

struct CourseList {
  std::string folder;              // the course folder; empty: none
  std::vector<ToothChoice> teeth;  // the built-in molar at each level, then the folder's .dvol files by name
  std::vector<TaskChoice> tasks;   // the folder's .json files by name, then the built-in tasks: a course comes first
  std::string error;               // why the folder cannot be read; empty when it can (or there is none)
};

// Builds the lists. `folder` empty: the built-in teeth and tasks only. Only the folder's own files
// are listed, not its subfolders'; a task file is read at most once per call.
CourseList listCourse(const std::string& folder);

// The task a student starts on: the course folder's first task that loads (by file name); empty
// when the folder holds none.
std::string firstCourseTask(const CourseList& list);

// A task's line in the picker, with the student's record when there is one: "class1.json  best
// 82 of 3, passed" ("does not load" for a broken file).
std::string taskPickerLine(const TaskChoice& t);

// The course folder `dentsim run` uses when none is given: "assets/tasks" under `cwd` when that is a
// folder, else empty.
std::string defaultCourseFolder(const std::string& cwd);

}  // namespace dentsim::ui
