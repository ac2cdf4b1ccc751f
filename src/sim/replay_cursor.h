// ReplayCursor: a recorded session replayed step for step on a HapticLoop, to any step and back to its start; the one replay that `replay` headless and in the window both run.
//
// The session's convention (sim/session_run.h): each tool's proxy starts on its pen's first
// reading, and a parameter set comes into force at the step the file names. A step of the loop
// depends on everything before it (the cut so far, the proxies, the turbine), so the cursor only
// moves forward; going back means restart() (the starting tooth restored, a fresh loop) and
// stepping forward again, which replays exactly what a straight run does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "io/pen_playback.h"
#include "io/session_file.h"
#include "model/tool_generator.h"
#include "sim/edit_channel.h"
#include "sim/guide_spring.h"
#include "sim/haptic_loop.h"
#include "sim/session_run.h"
#include "sim/sim_params.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct ReplayCursorOptions {
  bool allow_other_tooth = false;  // replay although the tooth's hash differs (a warning, not an error)
  // Receives every voxel edit (a window's copy of the tooth follows the cut); null: none. The
  // cursor stops stepping while the channel is half full, so that a cut never waits for room
  // (which would make the replay differ from the recording); the caller drains it and steps on.
  EditChannel* edits = nullptr;
};

class ReplayCursor {
 public:
  // Checks `session` against `tooth` (its starting volume, which the cursor cuts in place and
  // restores on restart()) and builds the loop at the session's first step. Both must outlive the
  // cursor. Errors: a tooth whose hash differs (unless allowed), a parameter set or tool that does
  // not load, a session without steps (or none before its first gap).
  static Result<std::unique_ptr<ReplayCursor>> open(const SessionRecording& session, ToothVolume& tooth,
                                                    const ReplayCursorOptions& options);
  ~ReplayCursor();
  ReplayCursor(const ReplayCursor&) = delete;
  ReplayCursor& operator=(const ReplayCursor&) = delete;

  // Steps that replay: the session's up to its first gap (past it the loop's state is unknown).
  size_t size() const { return steps_.size(); }
  std::span<const SessionStep> steps() const { return steps_; }
  size_t position() const { return position_; }  // steps played
  bool atEnd() const { return position_ == steps_.size(); }
  double rateHz() const { return rate_hz_; }
  double time() const { return double(position_) / rate_hz_; }       // loop time played [s]
  double duration() const { return double(steps_.size()) / rate_hz_; }  // loop time of the whole replay [s]

  // Plays the next step; the cursor must not be at the end.
  const StepReport& step();
  // Plays forward to `target` (clamped to size()), at most `max_steps` of them, and stops early
  // while the edit channel is half full. Returns the steps played. A target behind the position
  // plays nothing: restart() first.
  size_t stepTo(size_t target, size_t max_steps = SIZE_MAX);
  // Back to the start: the starting tooth, a fresh loop, the proxies on the first readings. The
  // caller's copy of the tooth (fed by the edit channel) must be reset to start() as well.
  void restart();

  // The loop: its latest() state shows where the tools are.
  HapticLoop& loop() { return *loop_; }
  const ToothVolume& tooth() const { return tooth_; }
  const ToothVolume& start() const { return start_; }
  // Steps so far whose drill force differs from the recorded one, and the first of them.
  uint64_t forceMismatches() const { return force_mismatches_; }
  uint64_t firstMismatch() const { return first_mismatch_; }
  // Truncation, gaps, another tooth: what the replay says beside its result.
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The replay as it stands: steps, the tooth's hash and removal, whether the recording ended on
  // the same hash, the force mismatches and every warning.
  ReplayOutcome outcome() const;

 private:
  ReplayCursor(const SessionRecording& session, ToothVolume& tooth, const ReplayCursorOptions& options);

  const SessionRecording& session_;
  ToothVolume& tooth_;
  ToothVolume start_;  // the tooth as the session found it, for restart()
  ReplayCursorOptions options_;
  SimParams params_;
  std::vector<SimParams> changes_;  // session_.params, parsed
  ToolModel drill_;
  std::optional<ToolModel> mirror_;
  std::optional<GuidePath> guide_path_;  // a guided session's guide, from its header
  std::optional<GuideSpring> guide_;     // the current loop's, rebuilt by restart()
  std::span<const SessionStep> steps_;
  std::vector<std::string> warnings_;
  double rate_hz_ = 1000.0;
  // The loop and its pens, rebuilt by restart(); the loop goes before the pens it reads.
  std::unique_ptr<ReplayPen> drill_pen_, mirror_pen_;
  std::unique_ptr<HapticLoop> loop_;
  size_t position_ = 0;
  size_t next_change_ = 0;
  uint64_t force_mismatches_ = 0;
  uint64_t first_mismatch_ = 0;
};

}  // namespace dentsim
