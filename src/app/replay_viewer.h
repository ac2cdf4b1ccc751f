// The replay window: a recorded session played on the tooth as it is cut, with the tools where the session's loop put them, a free camera, and the transport and force timeline of ui/replay_panel.h.
//
// The frame thread steps the replay itself (a ReplayCursor, like the simulator's lockstep): while
// playing, the playhead moves by the wall-clock time since the last frame times the speed, and the
// cursor plays up to it within a time budget a frame, so the window stays responsive at 8x. A seek
// forward plays on to the target; a seek back restarts the cursor (the starting tooth, a fresh
// loop) and plays up to the target, which is exactly what a straight replay does. The loop's voxel
// edits reach the window's copy of the tooth through the edit channel, and the changed bricks are
// re-meshed, as in `dentsim run`.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/frame_painter.h"
#include "core/result.h"
#include "io/session_file.h"
#include "sim/session_run.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// The run whose window a review replays in: its painter (window, device, surfaces: the run builds
// its tooth's surfaces again afterwards), the camera its mouse steers, and whether it was asked to end.
struct ReplayHost {
  FramePainter* painter = nullptr;
  const render::OrbitCamera* camera = nullptr;  // copied into the replay's view each frame
  std::function<bool()> quit;                   // Escape or Ctrl-C in the run: the review ends too
};

struct ReplayViewerOptions {
  std::string title;               // the session's name, in the window's title and the panel
  int width = 1280, height = 800;  // the window [px]
  std::string device;              // Vulkan device index or name part; empty: the best
  double speed = 1.0;              // one of ui::kReplaySpeeds
  double force_threshold_n = 3.0;  // the task's force_error_n, marked on the timeline [N]
  bool allow_other_tooth = false;
  bool exit_at_end = false;        // close the window once the last step has played and at_end has run
  // Scripted seeks for tests and demonstrations: when the playhead first reaches `from_s`, it jumps to `to_s`.
  struct Seek {
    double from_s = 0.0, to_s = 0.0;
  };
  std::optional<Seek> seek_at;
  // Screenshots of the window when the playhead first reaches each of `shots_s`, written into `out`
  // as `dentsim run` writes its own (shot-N.png with shot-N.json; app/screenshots.h).
  std::vector<double> shots_s;     // [s of loop time]
  std::string out;                 // the folder; empty: no screenshots
  // The deprecated --shot-at: one screenshot when the playhead first reaches `shot_at_s`, written to shot_png alone.
  double shot_at_s = -1.0;
  std::string shot_png;
  // Runs once, the first time the playhead reaches the last step, with the replay's outcome and the
  // cut tooth (a copy: saving compacts a volume, and the replay's own stays as its loop needs it):
  // it writes the files and prints what headless prints, and returns the exit code.
  std::function<int(const ReplayOutcome& outcome, ToothVolume& final_tooth)> at_end;
  // The review after a score (app/simulator_review.cpp): the replay runs inside `dentsim run`'s
  // window instead of one of its own, the panel offers Back, and closing the window or Back returns.
  const ReplayHost* host = nullptr;
  // A professional's session (.dses) whose tools are drawn translucent beside the replay's, posed at
  // the replay's loop time (the run's ghost, app/ghost.h); empty: none. Never in the replay's loop.
  std::string ghost;
  float ghost_opacity = 0.4f;      // [0, 1]
  // The playhead moves 1/fps of loop time (times the speed) each frame and the steps play up to it
  // whatever they take, so that a picture at a replay time is the same on any machine (the run's --lockstep).
  bool lockstep = false;
  double fps = 30.0;               // [frames/s]
};

// Opens the window and plays `session` on `tooth` (its starting volume; afterwards as the replay
// left it) until the window closes (or, with exit_at_end, the replay ends). Returns at_end's exit
// code, or 1 with a message when the window closed before the end while `at_end` had files to
// write (`outputs_pending`). Errors: the session's (ReplayCursor::open), the window's or the GPU's.
Result<int> runReplayViewer(const SessionRecording& session, ToothVolume& tooth, const ReplayViewerOptions& options,
                            bool outputs_pending);

}  // namespace dentsim::app
