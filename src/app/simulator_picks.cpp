// The simulator's picks from the panel: a new tooth or task restarting as a new segment, and teacher mode's Record as ideal.
//
// Each leaves the run going on something sound: a tooth or task that does not load leaves the one
// in use, with the error in the panel; only a device or disk failure ends the run.
#include <filesystem>

#include "app/simulator_state.h"
#include "app/tool_placement.h"
#include "eval/cut_score.h"
#include "eval/task_ideal.h"
#include "ui/course_list.h"
#include "volume/tooth_file.h"

namespace dentsim::app {

// ---- a new tooth or task ---------------------------------------------------------------------------------

Status Simulator::restartOnNewTooth(const std::string& reason) {
  if (Status st = painter_->surfaces().build(view_.voxels); !st) return st;
  pending_dirty_.clear();
  score_shown_ = false;
  ui_.score = {};
  tooth_first_segment_ = segments_.count() + 1;
  if (pens_) {
    pens_->reset(PenRole::Drill, drillStartGrip(box_, 3.0));
    if (mirror_tool_) pens_->reset(PenRole::Mirror, mirrorGrip(box_, render::fromGlm(camera_.eye())));
  }
  note(reason + ": " + toothName() + ", level " + std::to_string(initial_.frame.level));
  return startSegment();
}

// The picker's tooth: a file that does not load leaves the tooth in use as it was, with the error
// in the panel.
Status Simulator::pickTooth() {
  const std::string file_before = tooth_file_;
  const int level_before = o_.level;
  tooth_file_ = ui_.tooth;
  if (tooth_file_.empty()) o_.level = ui_.level;
  const bool was_running = segments_.running();
  if (was_running)
    if (Status st = endSegment("new tooth"); !st) return st;
  if (Status st = loadTooth(); !st) {
    ui_.tooth_error = st.message();
    note(st.message());
    tooth_file_ = file_before;
    o_.level = level_before;
    ui_.tooth = tooth_file_;
    ui_.level = initial_.frame.level;
    // The tooth in use goes on where it was, in a new segment if one was running.
    return was_running ? startSegment() : Status(Ok{});
  }
  ui_.tooth_error.clear();
  ui_.level = initial_.frame.level;
  return restartOnNewTooth("new tooth");
}

// The picker's task: its tooth, level, tools and first view, as `run --task` would start it.
Status Simulator::pickTask() {
  auto task = builtinTask(ui_.task);
  if (!task) {
    ui_.task_error = task.message();
    note(task.message());
    ui_.task = task_source_;
    return Ok{};
  }
  const bool was_running = segments_.running();
  if (was_running)
    if (Status st = endSegment("new task"); !st) return st;
  const std::string file_before = tooth_file_;
  const int level_before = o_.level;
  tooth_file_ = task->tooth == kBuiltinMolarTooth ? "" : task->tooth;
  o_.level = task->level;
  if (Status st = loadTooth(); !st) {
    ui_.task_error = st.message();
    note(st.message());
    tooth_file_ = file_before;
    o_.level = level_before;
    ui_.task = task_source_;
    return was_running ? startSegment() : Status(Ok{});
  }
  ui_.task_error.clear();
  task_ = std::move(*task);
  task_source_ = ui_.task;
  // The task's tools and view; what the command line fixed (--bur, --mirror-tool, --view) stays.
  drill_name_ = o_.bur.empty() ? task_->drill_tool : o_.bur;
  ui_.bur = drill_name_;
  if (Status st = loadDrill(); !st) return st;
  mirror_name_ = o_.mirror_tool ? *o_.mirror_tool : task_->mirror_tool;
  if (Status st = loadMirror(); !st) return st;
  if (Status st = placeCamera(); !st) return st;
  showTask();
  return restartOnNewTooth("task " + task_->name);
}

// Teacher mode: the segment ends, its session is finished and its final tooth saved beside it, and
// both become the task file's ideal. The result, or why not, shows in the panel.
Status Simulator::recordIdeal() {
  // Not recording is the teacher's to read on the panel, not an error that ends the run.
  auto notRecorded = [&](const std::string& why) {
    ui_.ideal_status = "not recorded: " + why;
    note(ui_.ideal_status);
    return Status(Ok{});
  };
  if (!ui_.task_is_file) return notRecorded("the task is built in, not a file");
  if (!segments_.recording()) return notRecorded("this segment is not being recorded");
  if (Status st = endSegment("recorded as ideal"); !st) return st;
  const std::string session = segments_.sessionPath();
  const std::string final_path =
      outPath(std::filesystem::path(session).stem().string() + "-final.dvol");  // session-3-final.dvol
  ToothVolume final_tooth = cut_;  // saving compacts: a copy, so the tooth in use keeps its spare bricks
  if (Status st = saveTooth(final_path, final_tooth); !st) return notRecorded(st.message());
  out_.written.push_back(final_path);
  auto record = setTaskIdeal(task_source_, session, final_path);
  if (!record) return notRecorded(record.message());
  // The task file now names its new ideal: read it again, so that Score uses it.
  if (auto task = builtinTask(task_source_); task) task_ = std::move(*task);
  ui_.course = ui::listCourse(o_.course);  // the folder's files may have changed with it
  ui_.ideal_status = "ideal recorded in " + record->task_file + ": " + record->session_file + ", " + record->final_file;
  note(ui_.ideal_status);
  return Ok{};
}

}  // namespace dentsim::app
