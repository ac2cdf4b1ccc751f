// The simulator's side of the panel driver (sim_panel_driver.h): each call the panel's actions turn into (parameters, bur, reset, level, teacher folder), and the score made for the screen.
#include "app/score_screen.h"
#include "app/simulator_state.h"
#include "eval/cut_score.h"

namespace dentsim::app {

Status Simulator::handleActions(ui::PanelActions& a) {
  ui::applyPresetActions(a, *presets_, ui_);
  handleHelpActions(a);
  PanelAsks asks;
  asks.params_changed = a.params_changed;
  asks.normal_mode_changed = a.normal_mode_changed;
  asks.speed_changed = a.speed_changed;
  asks.task_changed = a.task_changed;
  asks.tooth_changed = a.tooth_changed;
  asks.record_ideal = a.record_ideal;
  asks.stop = a.stop;
  asks.start = a.start;
  asks.bur_changed = a.bur_changed;
  asks.level_changed = a.level_changed;
  asks.reset = a.reset;
  asks.score = a.score;
  return drivePanel(asks, *this);
}

Status Simulator::applyParams() {
  model_.params = ui_.params;
  model_.looks = ui_.looks;
  if (segments_.recorder()) segments_.recorder()->setParams(model_.params, ui::presetJson({model_.params, model_.looks}));
  else if (segments_.loop()) segments_.loop()->setParams(model_.params);
  return Ok{};
}

void Simulator::applyNormalMode() { painter_->surfaces().setNormalMode(model_.looks.view.normals); }

void Simulator::applyPedal() {
  if (pens_) pens_->setPedal(ui_.turbine_speed);
}

Status Simulator::teacherFolder() { return ui_.teacher && o_.out.empty() ? recordingFolder() : Status(Ok{}); }

Status Simulator::changeBur() {
  model_.drill_name = ui_.bur;
  if (Status st = loadDrill(); !st) return st;
  note("drill: " + model_.drill_name);
  return Ok{};
}

void Simulator::keepFileLevel() {
  note("the voxel level applies to the built-in molar; " + model_.tooth.name() + " keeps its own grid");
  ui_.level = model_.initial.frame.level;
}

Status Simulator::rebuildTooth(bool new_level) {
  if (new_level) {
    model_.tooth.level = ui_.level;
    if (Status st = loadTooth(); !st) return st;
  } else {
    state_.cut = model_.initial;
    state_.view = model_.initial;
  }
  if (Status st = painter_->surfaces().build(state_.view.voxels); !st) return st;
  state_.score_shown = false;
  ui_.score = {};
  reductionMapNewTooth(new_level);
  state_.tooth_first_segment = segments_.count() + 1;  // the restored or rebuilt tooth starts uncut
  return Ok{};
}

Status Simulator::scoreNow() {
  if (!model_.task) return Ok{};
  // The session holds the whole cut when this tooth has had one segment only.
  ScoredCut cut;
  const int on_tooth = segments_.count() - state_.tooth_first_segment + 1;
  if (o_.out.empty())
    cut.no_session_reason = "no session was recorded (no --out folder)";
  else if (on_tooth > 1)
    cut.no_session_reason = "the cut spans " + std::to_string(on_tooth) + " segments, and no one session holds it";
  else {
    cut.initial_file = segments_.initialPath();
    cut.session_file = segments_.sessionPath();
  }
  auto score = scoreForScreen(*model_.task, model_.initial, state_.view, cut, o_.out);
  if (!score) return score.error();
  state_.final_saved = !o_.out.empty();
  ui_.score = score->panel;
  state_.panel_relayout = true;  // the Score page appears and comes forward
  if (Status st = painter_->renderer().setOverlayImage(score->picture); !st) return st;
  state_.score_shown = true;
  // The score's picture takes the window from the reduction map until the tooth changes again.
  state_.score_picture = score->picture;
  ui_.reduction.on_screen = false;
  map_.discard();
  out_.score = score->total;
  note(score->summary);
  for (const std::string& w : score->warnings) noteWarning(w);
  for (std::string& f : score->written) out_.written.push_back(std::move(f));
  if (o_.on_scored) {
    o_.on_scored(*model_.task, score->report, cut.session_file, state_.final_saved ? outPath("final.dvol") : "");
    // The score report names its learning record's statement, so that a class report counts it once.
    if (state_.final_saved && score->report.contains("statement_id"))
      if (Status st = writeScoreReport(outPath("score.json"), score->report); !st) return st;
  }
  // After the record is added: the review's buttons, and this attempt against the last ones.
  prepareReview(cut.session_file, cut.no_session_reason, score->report);
  return Ok{};
}

}  // namespace dentsim::app
