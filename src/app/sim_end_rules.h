// When the simulator's run quits by itself: the loop time given, the bench's frames, the pen script's end (with its last frame, its linger), full detail reached, a closed window or Ctrl-C; pure logic, so it is tested without a window.
//
// The frame loop asks in this order each frame, after the frame is counted: limits() (the loop
// time and the bench's frames), scriptEnds() (the simulator then ends the segment, scores, asks for
// the last shot and calls scriptEnded()), then afterScript() (the last frame shown, the linger up).
// Wall times are seconds on one steady clock, chosen by the caller, so a test needs none.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace dentsim::app {

// When the run quits by itself; with none of these it runs until the window closes.
struct SimEndOptions {
  double exit_after_s = 0.0;            // quit at this loop time; 0: when the window closes, or
                                        // headless, when the script ends (a virtual pen needs it) [s]
  bool exit_at_end = false;             // quit one frame after the script ends (windowed too)
  double linger_s = -1.0;               // windowed: quit this long after the script's end (and its score) [wall s]; < 0: stay
  bool quit_at_full_detail = false;     // with progressive: quit once the full copy is whole (benchmarks)
  int bench_frames = 0;                 // > 0: draw every frame (headless too), stop after this many
  double bench_from_s = 0.0;            // ... from this loop time on (the script's steps before run undrawn) [s]
};

class EndRules {
 public:
  // A script's pens stop this long after its last sample before the segment is called complete,
  // so that the last cut's edits have reached the frame loop [s of loop time].
  static constexpr double kScriptSettleS = 0.2;
  // Loop times compare with this slack, so that k / fps reaches a time given in decimal [s].
  static constexpr double kLoopTimeSlackS = 1e-9;

  // `script_end_s`: the pen script's last sample [s of loop time]; none without a script.
  EndRules(const SimEndOptions& options, bool headless, std::optional<double> script_end_s)
      : o_(options), headless_(headless), script_end_s_(script_end_s) {}

  bool quit() const { return quit_; }
  // Why the run stopped early ("the window was closed"), for "not scored"; empty: it did not.
  const std::string& reason() const { return reason_; }
  // Stops the run with a reason that a score not made is blamed on.
  void stop(const std::string& reason) {
    quit_ = true;
    reason_ = reason;
  }
  // Stops the run with no reason of its own (Escape, a pen's fatal fault, the bench done).
  void stopQuietly() { quit_ = true; }

  // A benchmark draws every frame from bench_from_s on, headless too.
  bool benchDraws(double loop_t) const { return o_.bench_frames > 0 && loop_t >= o_.bench_from_s - kLoopTimeSlackS; }
  // The first frames build the pipelines' caches and the panel's layout: a benchmark's frame times leave them out.
  int warmUpFramesLeftOut() const { return o_.bench_frames > 0 ? 3 : 0; }

  void fullDetailReached() {
    if (o_.quit_at_full_detail) quit_ = true;
  }

  // The loop time given and the bench's frames.
  void limits(double loop_t, uint64_t frames_drawn) {
    if (o_.exit_after_s > 0 && loop_t >= o_.exit_after_s - kLoopTimeSlackS) stop("--exit-after ended the run");
    if (o_.bench_frames > 0 && frames_drawn >= uint64_t(o_.bench_frames)) quit_ = true;
  }

  // True on the frame the script has played out while its segment still runs.
  bool scriptEnds(double loop_t, bool segment_running) const {
    return script_end_s_ && segment_running && loop_t >= *script_end_s_ + kScriptSettleS;
  }
  // The script's end was carried out at wall time `wall_s`: headless (with no loop time given) or
  // with exit_at_end the run quits once its last frame is shown; the linger counts from here.
  void scriptEnded(double wall_s) {
    if ((headless_ && o_.exit_after_s <= 0) || o_.exit_at_end) quit_after_last_frame_ = true;
    script_ended_ = true;
    ended_at_s_ = wall_s;
  }

  // After the script's end: the last frame shown (no shot pending), or the linger up in a window.
  void afterScript(bool last_shot_pending, bool segment_running, double wall_s) {
    if (quit_after_last_frame_ && !last_shot_pending && !segment_running) quit_ = true;
    if (script_ended_ && o_.linger_s >= 0 && !segment_running && wall_s - ended_at_s_ >= o_.linger_s) quit_ = true;
  }

 private:
  SimEndOptions o_;
  bool headless_ = false;
  std::optional<double> script_end_s_;  // the script's last sample [s of loop time]
  bool quit_ = false;
  std::string reason_;
  bool quit_after_last_frame_ = false;
  // When the script's end was carried out [wall s]. A flag beside a plain double rather than an
  // optional: GCC's -O1 sanitizer build takes the optional's read for an uninitialized one.
  bool script_ended_ = false;
  double ended_at_s_ = 0.0;
};

}  // namespace dentsim::app
