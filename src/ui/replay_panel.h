// The replay window's transport and timeline: play/pause, the speeds, and a strip of the drill's force and contact over the session that the user drags to seek.
//
// Immediate mode like the parameter window (ui/param_panel.h): call drawReplayPanel once a frame
// between ImGuiLayer::newFrame and render; it never touches the replay itself, and the app carries
// out the ReplayPanelActions it returns. The window sits along the bottom edge, full width.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/pixel_rect.h"
#include "io/session_file.h"

namespace dentsim::ui {

// The transport's speeds: loop time played per wall-clock second.
inline constexpr std::array<double, 6> kReplaySpeeds{0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
// The index of `speed` in kReplaySpeeds, or none when it is not one of them.
std::optional<int> replaySpeedIndex(double speed);

// One pixel column of the timeline: the steps it covers, summed up.
struct ForceColumn {
  float max_force_n = 0.0f;  // the largest |drill force| of its steps [N]
  bool contact = false;      // some step had the drill in tissue (contacts > 0)
  bool over = false;         // some step was in contact with a force over the threshold: the
                             // steps a score counts in force_over (eval/session_stats.h)
};

// The drill's force of `steps` in `columns` columns (at least 1): column c covers steps
// [c * n / columns, (c + 1) * n / columns), and keeps their maximum, so that a short spike still shows.
std::vector<ForceColumn> forceColumns(std::span<const SessionStep> steps, double threshold_n, int columns);

struct ReplayPanelState {
  std::string title;                // the session's name
  bool playing = true;
  int speed_index = 2;              // into kReplaySpeeds
  double time_s = 0.0;              // the playhead: loop time played [s]
  double duration_s = 0.0;          // the whole replay [s]
  std::span<const SessionStep> steps;  // what the strip shows; must outlive the panel's use
  double threshold_n = 3.0;         // a contact step over this force is an error [N]
  std::string status;               // one line under the timeline ("wrote final.dvol")
  // The strip's columns, recomputed by the panel when its width changes.
  std::vector<ForceColumn> columns;
  int columns_width = 0;
  float strip_top_n = 0.0f;         // the strip's full scale [N]
  std::optional<double> drag_s;     // where the playhead is being dragged [s]
  bool back_shown = false;          // a Back button: the replay is a review inside `dentsim run`
};

struct ReplayPanelActions {
  bool toggle_play = false;         // the Play/Pause button or Space
  bool speed_changed = false;       // state.speed_index changed
  std::optional<double> seek_s;     // the playhead was dragged (and let go) or stepped here [s]
  bool back = false;                // Back: the review ends, the run goes on
  std::optional<double> hover_s;    // where the pointer is over the strip [s]
  PixelRect panel_rect;             // the window, for the scene to keep clear of
  PixelRect strip_rect;             // the force strip
};

// Draws the "Replay" window. While the strip is dragged, the playhead follows the pointer and the
// seek comes when the button is let go (a seek back re-cuts from the start: once, not every frame).
ReplayPanelActions drawReplayPanel(ReplayPanelState& state);

// "1:05.3": minutes and seconds to a tenth.
std::string replayClock(double seconds);

}  // namespace dentsim::ui
