// The panel driver: what one frame of the parameter panel asked for, turned into the simulator's calls in the one order that keeps the recording sound (picks, then Stop and Start, the bur, Reset, Score); pure logic against an interface, so it is tested with a fake simulator.
//
// Every change that alters what the haptic loop cuts with (a new bur, a rebuilt tooth) ends the
// running segment first and starts a new one after, so that each session holds one tool and one
// starting tooth. Whether a segment runs is asked again at each point, because a pick or Record
// as ideal may itself end or start one.
#pragma once

#include <string>

#include "core/result.h"

namespace dentsim::app {

// What the panel asked for this frame (ui::PanelActions, after its preset requests were carried out).
struct PanelAsks {
  bool params_changed = false;       // the tissues' or looks' parameters
  bool normal_mode_changed = false;  // the normals' neighbourhood: re-mesh
  bool speed_changed = false;        // the turbine speed (no pedal only)
  bool task_changed = false;         // a new task from the picker
  bool tooth_changed = false;        // a new tooth from the picker
  bool record_ideal = false;         // teacher mode's Record as ideal
  bool stop = false, start = false;  // the segment's buttons
  bool bur_changed = false;          // a bur picked (maybe the one in use)
  bool level_changed = false;        // the built-in molar's level
  bool reset = false;                // back to the uncut tooth
  bool score = false;                // score the cut now
};

// The simulator as the panel driver sees it.
class PanelTarget {
 public:
  virtual ~PanelTarget() = default;
  virtual Status applyParams() = 0;          // the panel's parameters to the loop and its recorder
  virtual void applyNormalMode() = 0;
  virtual void applyPedal() = 0;             // the panel's turbine speed to the virtual pedal
  virtual Status teacherFolder() = 0;        // teacher mode without --out: a temporary folder (no-op otherwise)
  virtual Status pickTask() = 0;
  virtual Status pickTooth() = 0;
  virtual Status recordIdeal() = 0;
  virtual bool segmentRunning() const = 0;
  virtual Status endSegment(const std::string& reason) = 0;
  virtual Status startSegment() = 0;
  virtual bool burDiffers() const = 0;       // the panel's bur is not the one on the drill
  virtual Status changeBur() = 0;            // loads the panel's bur onto the drill
  virtual bool builtinTooth() const = 0;
  virtual void keepFileLevel() = 0;          // a level asked of a tooth file: said, and the picker put back
  virtual Status rebuildTooth(bool new_level) = 0;  // the uncut tooth again (at the panel's level when new_level)
  virtual Status scoreNow() = 0;
};

// Carries out `a` on `t`; the first error ends it (and the run).
inline Status drivePanel(const PanelAsks& a, PanelTarget& t) {
  if (a.params_changed)
    if (Status st = t.applyParams(); !st) return st;
  if (a.normal_mode_changed) t.applyNormalMode();
  if (a.speed_changed) t.applyPedal();
  // Teacher mode needs its segments recorded: without --out they go to a temporary folder from the
  // next segment on (Reset starts one).
  if (Status st = t.teacherFolder(); !st) return st;
  // A new task brings its own tooth, so a tooth picked in the same frame gives way to it.
  if (a.task_changed)
    if (Status st = t.pickTask(); !st) return st;
  if (a.tooth_changed && !a.task_changed)
    if (Status st = t.pickTooth(); !st) return st;
  if (a.record_ideal)
    if (Status st = t.recordIdeal(); !st) return st;
  const bool running = t.segmentRunning();
  if (a.stop && running)
    if (Status st = t.endSegment("stopped"); !st) return st;
  if (a.start && !running)
    if (Status st = t.startSegment(); !st) return st;
  if (a.bur_changed && t.burDiffers()) {
    if (running)
      if (Status st = t.endSegment("bur changed"); !st) return st;
    if (Status st = t.changeBur(); !st) return st;
    if (running)
      if (Status st = t.startSegment(); !st) return st;
  }
  if (a.level_changed && !t.builtinTooth()) t.keepFileLevel();
  if (a.reset || (a.level_changed && t.builtinTooth())) {
    if (running)
      if (Status st = t.endSegment("reset"); !st) return st;
    if (Status st = t.rebuildTooth(a.level_changed); !st) return st;
    if (Status st = t.startSegment(); !st) return st;
  }
  if (a.score) {
    if (t.segmentRunning())
      if (Status st = t.endSegment("scored"); !st) return st;
    if (Status st = t.scoreNow(); !st) return st;
  }
  return Ok{};
}

}  // namespace dentsim::app
