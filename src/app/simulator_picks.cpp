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
  if (Status st = painter_->surfaces().build(state_.view.voxels); !st) return st;
  state_.pending_dirty.clear();
  state_.score_shown = false;
  ui_.score = {};
  reductionMapNewTooth(true);
  state_.tooth_first_segment = segments_.count() + 1;
  helpNewTooth();
  if (pens_) {
    pens_->reset(PenRole::Drill, drillStartGrip(model_.box, 3.0));
    if (model_.mirror_tool) pens_->reset(PenRole::Mirror, mirrorGrip(model_.box, render::fromGlm(camera_.eye())));
  }
  note(reason + ": " + model_.tooth.name() + ", level " + std::to_string(model_.initial.frame.level));
  return startSegment();
}

// The picker's tooth: a file that does not load leaves the tooth in use as it was, with the error
// in the panel.
Status Simulator::pickTooth() {
  const ToothChoice before = model_.tooth;
  model_.tooth = before.picked(ui_.tooth, ui_.level);
  const bool was_running = segments_.running();
  if (was_running)
    if (Status st = endSegment("new tooth"); !st) return st;
  if (Status st = loadTooth(); !st) {
    ui_.tooth_error = st.message();
    note(st.message());
    model_.tooth = before;
    ui_.tooth = model_.tooth.file;
    ui_.level = model_.initial.frame.level;
    // The tooth in use goes on where it was, in a new segment if one was running.
    return was_running ? startSegment() : Status(Ok{});
  }
  ui_.tooth_error.clear();
  ui_.level = model_.initial.frame.level;
  return restartOnNewTooth("new tooth");
}

// The picker's task: its tooth, level, tools and first view, as `run --task` would start it.
Status Simulator::pickTask() {
  auto task = builtinTask(ui_.task);
  if (!task) {
    ui_.task_error = task.message();
    note(task.message());
    ui_.task = model_.task_source;
    return Ok{};
  }
  const bool was_running = segments_.running();
  if (was_running)
    if (Status st = endSegment("new task"); !st) return st;
  const ToothChoice before = model_.tooth;
  model_.tooth = ToothChoice::ofTask(task->tooth, task->level);
  if (Status st = loadTooth(); !st) {
    ui_.task_error = st.message();
    note(st.message());
    model_.tooth = before;
    ui_.task = model_.task_source;
    return was_running ? startSegment() : Status(Ok{});
  }
  ui_.task_error.clear();
  model_.task = std::move(*task);
  model_.task_source = ui_.task;
  // The task's tools and view; what the command line fixed (--bur, --mirror-tool, --view) stays.
  model_.drill_name = o_.bur.empty() ? model_.task->drill_tool : o_.bur;
  ui_.bur = model_.drill_name;
  if (Status st = loadDrill(); !st) return st;
  model_.mirror_name = o_.mirror_tool ? *o_.mirror_tool : model_.task->mirror_tool;
  if (Status st = loadMirror(); !st) return st;
  if (Status st = placeCamera(); !st) return st;
  showTask();
  return restartOnNewTooth("task " + model_.task->name);
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
  ToothVolume final_tooth = state_.cut;  // saving compacts: a copy, so the tooth in use keeps its spare bricks
  if (Status st = saveTooth(final_path, final_tooth); !st) return notRecorded(st.message());
  out_.written.push_back(final_path);
  auto record = setTaskIdeal(model_.task_source, session, final_path);
  if (!record) return notRecorded(record.message());
  // The task file now names its new ideal: read it again, so that Score uses it.
  if (auto task = builtinTask(model_.task_source); task) model_.task = std::move(*task);
  ui_.course = ui::listCourse(o_.course);  // the folder's files may have changed with it
  showRecords();                           // and the student's attempts beside them
  ui_.ideal_status = "ideal recorded in " + record->task_file + ": " + record->session_file + ", " + record->final_file;
  note(ui_.ideal_status);
  return Ok{};
}

}  // namespace dentsim::app
