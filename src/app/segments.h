// The simulator's segments: a haptic loop and its session recording from Start to Stop, numbered, with the loop time carried across them.
//
// Reset, a new bur or a new level end a segment and start another on the current (or restored, or
// rebuilt) tooth, with its own starting tooth file and session file, so that every segment replays
// on its own: segment 1 writes initial.dvol and session.dses, segment n initial-n.dvol and session-n.dses.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/pen_source.h"
#include "core/result.h"
#include "sim/edit_channel.h"
#include "sim/guide_spring.h"
#include "sim/haptic_loop.h"
#include "sim/session_recorder.h"
#include "sim/sim_params.h"
#include "sim/tool_proxy.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// What every segment's loop and session are made of.
struct SegmentSetup {
  const SimParams* params = nullptr;
  const ToolModel* drill = nullptr;
  const ToolModel* mirror = nullptr;    // none: no mirror
  std::array<PenSource*, 2> pens{};     // by PenRole; null where none
  std::string drill_name, mirror_name;  // for the session's header
  std::string task_name;                // empty: free drilling
  std::string tooth_source;             // how the tooth was made (SessionInfo::tooth_source)
  int idle_latency_us = 0;              // HapticLoop::setIdleLatencyUs
  bool lockstep = false;                // the caller steps the loop (stepTo); else its real-time thread runs
  std::string out;                      // folder for the tooth and session files; empty: nothing recorded
  std::string params_json;              // the whole preset the session records (ui::presetJson of *params
                                        // and the looks); empty: simParamsJson(*params)
  const GuidePath* guide = nullptr;     // a guide's spring on the drill; none: unguided
  bool guide_goes_on = false;           // the guide starts where the last segment's stopped (the same tooth)
};

class Segments {
 public:
  // Starts the next segment on `tooth`, which the loop cuts: saves it first (saving compacts the
  // volume, which would drop the spare bricks the loop reserves for cutting), then records.
  // Files written are added to *written.
  Status start(ToothVolume& tooth, const SegmentSetup& setup, std::vector<std::string>* written);
  // Stops the loop (the caller has zeroed the pens' force) and closes the session with its end
  // record, the final hash of `tooth`. The tools stay where they were, at rest.
  Status end(const std::string& reason, const ToothVolume& tooth, std::vector<std::string>* written);

  bool running() const { return loop_ != nullptr; }
  HapticLoop* loop() const { return loop_.get(); }
  SessionRecorder* recorder() const { return recorder_.get(); }
  // The loop's voxel edits so far, applied to the frame loop's copy of the tooth; the bricks they
  // changed are added to *dirty.
  void drainEdits(BrickVolume& view, std::vector<BrickCoord>* dirty);
  int count() const { return count_; }
  // The current segment's files, or the last one's while stopped; empty when not recorded (no --out).
  const std::string& initialPath() const { return initial_path_; }
  const std::string& sessionPath() const { return last_session_path_; }
  bool recording() const { return recorder_ != nullptr; }
  // What the loop shows now, or what the last segment ended on while stopped.
  HapticState state() const { return loop_ ? loop_->latest() : last_state_; }
  // Steps of the current segment; while its thread runs, only the thread's atomic counter is read.
  uint64_t steps() const;
  uint64_t stepsDone() const { return steps_done_; }            // of finished segments
  uint64_t stepsAll() const { return steps_done_ + (loop_ ? steps() : 0); }
  double removedDoneMm3() const { return removed_done_mm3_; }   // by finished segments
  double removedMm3() const { return removed_done_mm3_ + (loop_ ? loop_->latest().removed_mm3 : 0.0); }
  // Loop time [s]: carried across segments, so that screenshots and scripts see one clock.
  double loopTime() const;
  // In lockstep: steps the loop until loop time reaches t, letting the recorder keep up.
  void stepTo(double t);
  // Stopped and headless, loop time follows the frames.
  void holdTimeAtLeast(double t) { t0_ = std::max(t0_, t); }
  // The permission line of the first segment whose loop thread was refused the idle-latency request
  // (IdleLatencyRequest::note), once: empty before that and after it was taken.
  std::string takeIdleLatencyDenial() { return std::exchange(idle_latency_denial_, std::string()); }

 private:
  // Declared before the loop, so that it outlives a loop whose thread may still be stepping.
  std::optional<GuideSpring> guide_;  // the current or last segment's; the loop points at it
  std::unique_ptr<HapticLoop> loop_;
  std::unique_ptr<SessionRecorder> recorder_;
  std::string session_path_;       // the session being recorded; empty when none
  std::string last_session_path_;  // the current or last segment's session file
  std::string initial_path_;       // the current or last segment's starting tooth file
  EditChannel edits_;
  std::vector<uint64_t> batch_;
  HapticState last_state_;
  double rate_hz_ = 1000.0;
  bool lockstep_ = false;
  int count_ = 0;
  uint64_t steps_done_ = 0;
  double removed_done_mm3_ = 0.0;
  std::string idle_latency_denial_;  // not yet taken
  bool idle_latency_denial_seen_ = false;
  double t0_ = 0.0;  // loop time at the current segment's start [s]
};

}  // namespace dentsim::app
