// Building the pickers' lists from the embedded tasks and a course folder.
#include "ui/course_list.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "eval/cut_score.h"
#include "io/dvol_file.h"
#include "model/builtin_assets.h"

namespace dentsim::ui {
namespace {

namespace fs = std::filesystem;

// A task as the picker shows it, from builtinTask's answer for `source`.
TaskChoice taskChoice(const std::string& source, const std::string& label, bool builtin) {
  TaskChoice c;
  c.source = source;
  c.label = label;
  c.builtin = builtin;
  auto task = builtinTask(source);
  if (!task) {
    c.error = task.message();
    return c;
  }
  c.title = task->title;
  c.instructions = task->instructions;
  c.name = task->name;
  c.pass_mark = task->pass_mark;
  return c;
}

// The regular files in `folder` ending in `ext`, sorted by name; *error says why it could not be read.
std::vector<fs::path> filesWithExtension(const std::string& folder, const std::string& ext, std::string* error) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->path().extension() == ext && it->is_regular_file(type_ec)) files.push_back(it->path());
  }
  if (ec) *error = folder + ": cannot read the course folder: " + ec.message();
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

CourseList listCourse(const std::string& folder) {
  CourseList list;
  list.folder = folder;
  for (int level = kMinLevel; level <= kMaxLevel; ++level)
    list.teeth.push_back({"built-in molar, level " + std::to_string(level), "", level});
  // Every embedded task file, by the name builtinTask knows it by (its stem); after the course's own.
  std::vector<TaskChoice> builtins;
  for (const std::string& asset : builtinAssetPaths()) {
    const fs::path p(asset);
    if (p.parent_path() != "tasks" || p.extension() != ".json") continue;
    const std::string name = p.stem().string();
    builtins.push_back(taskChoice(name, name, true));  // a file shows as "name.json"
  }
  if (folder.empty()) {
    list.tasks = std::move(builtins);
    return list;
  }
  // A tooth whose layers were synthesized from one surface says so where it is picked: its enamel
  // and pulp are a model's, and a student drilling it should know. Only the header is read; a file
  // that does not load keeps its plain name and fails, with its reason, when picked.
  for (const fs::path& f : filesWithExtension(folder, ".dvol", &list.error)) {
    const Result<bool> synthesized = readLayersSynthesized(f.string());
    const std::string note = synthesized.ok() && *synthesized ? " (synthesized layers)" : "";
    list.teeth.push_back({f.filename().string() + note, f.string(), 0});
  }
  std::string ignored;  // the same folder: its error is already kept
  for (const fs::path& f : filesWithExtension(folder, ".json", &ignored))
    list.tasks.push_back(taskChoice(f.string(), f.filename().string(), false));
  // The course first: a student opens the picker on the exercises set, not on the built-in ones.
  for (TaskChoice& t : builtins) list.tasks.push_back(std::move(t));
  return list;
}

std::string firstCourseTask(const CourseList& list) {
  for (const TaskChoice& t : list.tasks)
    if (!t.builtin && t.error.empty()) return t.source;
  return "";
}

std::string taskPickerLine(const TaskChoice& t) {
  if (!t.error.empty()) return t.label + " (does not load)";
  if (t.attempts == 0) return t.label;
  char best[32];
  std::snprintf(best, sizeof best, "%.0f", t.best.value_or(0.0));
  std::string line = t.label + "  best " + best + " of " + std::to_string(t.attempts);
  if (t.passed) line += ", passed";
  return line;
}

std::string defaultCourseFolder(const std::string& cwd) {
  const fs::path tasks = fs::path(cwd) / "assets" / "tasks";
  std::error_code ec;
  return fs::is_directory(tasks, ec) ? tasks.string() : std::string();
}

}  // namespace dentsim::ui
