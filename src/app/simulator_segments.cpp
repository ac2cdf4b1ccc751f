// The simulator's segments: one started on the tooth as it is (loop, recorder, forces on), one ended (forces off, the session closed, the loop's last edits drawn).
#include "app/simulator_state.h"

namespace dentsim::app {

Status Simulator::startSegment() {
  SegmentSetup s;
  s.params = &model_.params;
  s.params_json = ui::presetJson({model_.params, model_.looks});
  s.drill = &*model_.drill_tool;
  s.mirror = model_.mirror_tool ? &*model_.mirror_tool : nullptr;
  s.pens = {rack_.pen(PenRole::Drill), rack_.pen(PenRole::Mirror)};
  s.drill_name = model_.drill_name;
  s.mirror_name = model_.mirror_name;
  s.task_name = model_.task ? model_.task->name : "";
  s.tooth_source = model_.tooth.builtin() ? builtinToothSource(model_.tooth.level) : model_.tooth.name();
  s.idle_latency_us = o_.idle_latency_us;
  s.lockstep = lockstep_;
  s.out = o_.out;
  s.guide = segmentGuide();  // the panel's switch: --guide's path or the task's professional
  s.guide_goes_on = state_.tooth_first_segment <= segments_.count();  // not the first segment on this tooth
  if (Status st = segments_.start(state_.cut, s, &out_.written); !st) return st;
  restartGhost();
  state_.final_saved = false;
  ui_.segment_recorded = segments_.recording();
  // Forces may go out only now that the loop commands them every step (the watchdog counts from here).
  rack_.enable();
  stats_.rate_steps = segments_.stepsDone();
  stats_.rate_t0 = Clock::now();
  if (segments_.count() == 1) stats_.haptic_t0 = stats_.rate_t0;
  ui_.run_state = ui::RunState::Running;
  return Ok{};
}

Status Simulator::endSegment(const std::string& reason) {
  if (!segments_.running()) return Ok{};
  // Zero force before the loop stops commanding it (else every pen would latch a watchdog fault).
  rack_.disable();
  Status result = segments_.end(reason, state_.cut, &out_.written);
  if (std::string denial = segments_.takeIdleLatencyDenial(); !denial.empty()) note("dentsim: " + denial);
  // The loop's last edits reach the frame loop's copy before the next loop starts.
  segments_.drainEdits(state_.view.voxels, &state_.pending_dirty);
  if (painter_)
    if (Status st = painter_->remesh(state_.view.voxels, &state_.pending_dirty); !st && result) result = st;
  out_.removed_mm3 = segments_.removedDoneMm3();
  ui_.run_state = ui::RunState::Stopped;
  ui_.segment_recorded = false;
  return result;
}

}  // namespace dentsim::app
