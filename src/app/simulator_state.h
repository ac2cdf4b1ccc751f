// The simulator's state, shared by its set-up (simulator_setup.cpp) and its frame loop (simulator.cpp); private to those two files.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/device_rack.h"
#include "app/frame_painter.h"
#include "app/ghost.h"
#include "app/run_sound.h"
#include "app/screenshots.h"
#include "app/segments.h"
#include "app/simulator.h"
#include "app/terminal_progress.h"
#include "app/window_input.h"
#include "eval/task.h"
#include "eval/task_tooth.h"
#include "render/camera.h"
#include "sim/surface_probe.h"
#include "sim/tool_proxy.h"
#include "ui/param_panel.h"
#include "ui/pen_input.h"
#include "ui/preset_store.h"

namespace dentsim::app {

class Simulator {
 public:
  using Clock = std::chrono::steady_clock;
  explicit Simulator(const SimulatorOptions& o)
      : o_(o), rack_(o.devices, [this](const std::string& text) { note(text); }),
        input_(camera_, box_, {[this](double speed) { ui_.turbine_speed = speed; }, [this] { quit_ = true; }}),
        shots_(o.shots_s, o.frame_every_s) {}
  Result<SimulatorOutcome> run();

 private:
  Status setUp();
  Status loadTooth();
  Status loadDrill();
  Status loadMirror();
  // The task's first view (or --view, or buccal raised 30 degrees), widened to take in the mirror where
  // it starts; a fixed task view locks the mouse and keys out.
  Status placeCamera();
  // After a new tooth or task: the surfaces rebuilt, the score cleared, the pens back at their
  // starts, and a new segment on the new tooth.
  Status restartOnNewTooth(const std::string& reason);
  Status pickTooth();   // the panel's tooth picker (ui_.tooth, ui_.level)
  Status pickTask();    // the panel's task picker (ui_.task)
  Status recordIdeal(); // teacher mode's "Record as ideal"
  void showTask();      // the task's title, instructions and kind in the panel
  Status recordingFolder();  // teacher mode without --out: a temporary folder for the sessions
  Status setUpScript(const Pose& mirror_start);
  Status startSegment();
  Status endSegment(const std::string& reason);
  Status frame();
  Status handleActions(ui::PanelActions& actions);
  Status scoreNow();
  render::FrameState frameState(const HapticState& state, VkExtent2D extent) const;
  Status drawFrame(const ShotSchedule::Due& due);
  // Pixels the scene moves left so that its centre is the middle of what the panel leaves free.
  int sceneShiftPx() const { return painter_->panel() ? panel_rect_.width / 2 : 0; }
  std::string outPath(const std::string& name) const { return (std::filesystem::path(o_.out) / name).string(); }
  void note(const std::string& text);
  // A warning: on stderr through warn(), as every command's, and on the panel's status line.
  void noteWarning(const std::string& text);
  // The tooth is the built-in molar (at o_.level) unless --tooth, the task or the picker named a volume file.
  bool builtinTooth() const { return tooth_file_.empty(); }
  std::string toothName() const { return builtinTooth() ? "built-in molar" : tooth_file_; }
  // Where the tooth is on screen, for the score picture to stay off it; empty when it is behind the eye.
  PixelRect toothRect(VkExtent2D extent) const;

  SimulatorOptions o_;
  SimulatorOutcome out_;
  bool headless_ = false;
  bool lockstep_ = false;

  // Tooth: the haptic loop's copy (cut), the frame loop's copy (view, fed by the edits), the start.
  ToothVolume initial_, cut_, view_;
  TissueBox box_;
  std::string tooth_file_;          // the tooth's volume file; empty: the built-in molar at o_.level
  int tooth_first_segment_ = 1;     // the first segment on this tooth (a score uses its session when it is the only one)
  std::optional<Task> task_;
  std::string task_source_;         // what the task was started from: a built-in name or a task file
  SimParams params_;
  LookParams looks_;  // the preset's visual half (one preset with params_)
  std::optional<ToolModel> drill_tool_, mirror_tool_;
  std::string drill_name_, mirror_name_;

  DeviceRack rack_;
  std::optional<PenPath> script_;
  std::optional<GuidePath> guide_;      // --guide's path, read once; every segment's spring starts from it
  double script_end_s_ = 0.0;
  std::unique_ptr<ui::PenInput> pens_;  // the mouse and keys move the virtual pens

  Segments segments_;
  std::vector<BrickCoord> pending_dirty_;  // edited bricks not yet re-meshed

  RunSound sound_;

  render::OrbitCamera camera_;
  WindowInput input_;                     // the window's callbacks point here: it outlives the window
  std::unique_ptr<FramePainter> painter_;
  ShotSchedule shots_;

  // Panel.
  ui::UiState ui_;
  std::unique_ptr<ui::PresetStore> presets_;
  ui::PanelActions last_actions_;
  bool score_shown_ = false;
  bool panel_relayout_ = true;   // the panel's next frame is laid out once unseen first (new tabs)
  PixelRect panel_rect_;  // the parameter window

  bool quit_ = false;
  bool quit_after_final_ = false;
  bool final_saved_ = false;             // final.dvol and the score's files hold the tooth as it is now
  std::optional<Clock::time_point> ended_at_;  // when the script ended (linger_s counts from here)
  std::string quit_reason_;              // why the run stopped early, for "not scored"

  // Timing.
  Clock::time_point run_t0_, last_frame_;
  Clock::time_point rate_t0_;    // the haptic rate shown is measured from here
  uint64_t rate_steps_ = 0;
  Clock::time_point haptic_t0_;  // the first segment's start
  std::vector<double> frame_ms_;
  double remesh_sum_ms_ = 0.0;
  uint64_t remesh_count_ = 0;
  double triangles_drawn_sum_ = 0.0;  // tooth triangles drawn, summed over drawn frames
  uint64_t final_triangles_ = 0;      // the full copy's surface after the last re-mesh
  TerminalProgress progress_;         // full detail filling in after the first frame
  // Wall time each frame gives the full copy's meshing while the first frames come in parts [ms]:
  // enough to finish a level-9 molar in a few seconds, little enough to keep the view moving.
  static constexpr double kDetailSliceMs = 40.0;

  // The professional's ghost (simulator_ghost.cpp): drawn only, never in the haptic loop.
  Status setUpGhost();                       // --ghost read (an error ends the run) and the panel's ghost state
  void restartGhost();                       // a segment starts: the ghost's task time from here
  void followGhost(const HapticState& state);  // this frame's ghost pose, loading it when first shown
  void showGhost(render::FrameState& fs) const;
  std::string ghostSource() const;           // --ghost, else the task's ideal session; empty: none
  Status loadGhost(const std::string& source);  // ghost_ read from `source`, its warnings noted
  std::optional<GhostDriver> ghost_;
  std::string ghost_failed_;                 // a source that did not load (not tried again)
  double ghost_t0_ = 0.0;                    // loop time at the segment's start [s]
};

}  // namespace dentsim::app
