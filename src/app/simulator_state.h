// The simulator's state, shared by its set-up (simulator_setup.cpp), its frame loop (simulator.cpp) and the parts of the frame in simulator_*.cpp; private to those files.
//
// As MuJoCo keeps mjModel (read-mostly) apart from mjData (changed each step), the Simulator keeps
// three plain structs: the run model (the tooth, task and tools, changed only by a pick or a
// reset), the run state (the cut, the segments' tooth bookkeeping, the panel's layout, what each
// frame changes) and the run statistics (measured, never read back by the run's logic). The parts
// that do one job each (device rack, segments, painter, sound, end rules) sit beside them.
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
#include "app/reduction_map.h"
#include "app/run_sound.h"
#include "app/screenshots.h"
#include "app/scripted_input.h"
#include "app/segments.h"
#include "app/sim_end_rules.h"
#include "app/sim_panel_driver.h"
#include "app/sim_tooth_choice.h"
#include "app/simulator.h"
#include "app/terminal_progress.h"
#include "app/window_input.h"
#include "eval/task.h"
#include "eval/task_tooth.h"
#include "render/camera.h"
#include "sim/novice_paths.h"
#include "sim/surface_probe.h"
#include "sim/tool_proxy.h"
#include "ui/param_panel.h"
#include "ui/pen_input.h"
#include "ui/preset_store.h"

namespace dentsim::app {

using SimClock = std::chrono::steady_clock;

// What the run is about: set up once, changed only by the panel's picks (tooth, task, bur) and
// level; every segment starts from it.
struct SimRunModel {
  ToothVolume initial;               // the uncut tooth, as loaded
  TissueBox box;                     // the uncut tooth's tissue bounds [mm, simulation frame]
  ToothChoice tooth;                 // which tooth that is, and from where
  std::optional<Task> task;          // the task scored
  std::string task_source;           // what the task was started from: a built-in name or a task file
  SimParams params;                  // the preset's simulation half
  LookParams looks;                  // the preset's visual half (one preset with params)
  std::optional<ToolModel> drill_tool, mirror_tool;  // loaded tools (point shells at params' spacing); no mirror_tool: none
  std::string drill_name, mirror_name;               // their catalogue names; empty mirror_name: none
  std::optional<PenPath> script;     // the pen path both pens play; none: mouse, keys or hardware pens
  double script_end_s = 0.0;         // the script's last sample [s of loop time]
  std::optional<GuidePath> guide;    // --guide's path, read once; every segment's spring starts from it
};

// What the frames change: the tooth as cut, the bricks waiting for a re-mesh, the panel's layout
// and score, and whether the files on disk still describe the tooth.
struct SimRunState {
  ToothVolume cut;                   // the haptic loop's copy of the tooth (the loop cuts it)
  ToothVolume view;                  // the frame loop's copy, fed by the loop's edits, drawn
  int tooth_first_segment = 1;       // the first segment on this tooth (a score uses its session when it is the only one)
  std::vector<BrickCoord> pending_dirty;  // edited bricks not yet re-meshed
  bool score_shown = false;          // the score picture is on screen
  ui::PanelActions last_actions;     // the panel's last drawn frame (where the score picture goes)
  bool panel_relayout = true;        // the panel's next frame is laid out once unseen first (new tabs)
  PixelRect panel_rect;              // the parameter window [px]
  PixelRect help_rect;               // the controls overlay [px]; empty: not shown
  bool final_saved = false;          // final.dvol and the score's files hold the tooth as it is now
  RgbImage score_picture;            // the last score's picture, shown again when the reduction map goes off
};

// The scored attempt the Score page's review replays, and the scripted clicks after a score.
struct SimReviewState {
  std::string session;               // the scored attempt's session; empty: none
  std::string statement_id;          // its learning record's id: left out of "your last attempts"
  int reviews = 0;                   // replays opened; their screenshots go to <out>/review-N
  size_t next_click = 0;             // into SimReviewOptions::presses
  std::string clicking;              // the widget pressed last frame, let go this one
  int waited_frames = 0;             // frames the next click has waited for its widget
};

// What the run measured, for its outcome; nothing the run decides reads it.
struct SimRunStats {
  SimClock::time_point run_t0;       // the run's start
  SimClock::time_point last_frame;   // the last drawn frame's end
  SimClock::time_point rate_t0;      // the haptic rate shown is measured from here
  uint64_t rate_steps = 0;           // loop steps done at rate_t0
  SimClock::time_point haptic_t0;    // the first segment's start
  std::vector<double> frame_ms;      // each drawn frame's time (windowed: frame to frame) [ms]
  double remesh_sum_ms = 0.0;        // incremental re-meshes, summed [ms]
  uint64_t remesh_count = 0;         // frames that re-meshed edits
  double triangles_drawn_sum = 0.0;  // tooth triangles drawn, summed over drawn frames
  uint64_t final_triangles = 0;      // the full copy's surface after the last re-mesh

  // The outcome's timing and throughput figures, `skip_frames` warm-up frames left out of the frame times.
  void fill(SimulatorOutcome& out, int skip_frames) const;
};

// What one frame does, decided once its loop time is known.
struct FramePlan {
  double t = 0.0;                    // the frame's loop time [s]
  ShotSchedule::Due due;             // the pictures it writes
  bool draw = false;                 // headless, a frame nobody sees is not drawn
  SimClock::time_point draw_t0;      // where a headless frame's own time starts (after the haptic steps)
  bool picture() const { return !due.shot_stem.empty() || !due.frame_stem.empty(); }
};

class Simulator : private PanelTarget {
 public:
  using Clock = SimClock;
  explicit Simulator(const SimulatorOptions& o)
      : o_(o), rack_(o.devices, [this](const std::string& text) { note(text); }),
        input_(camera_, model_.box,
               {[this](double speed) { ui_.turbine_speed = speed; }, [this] { end_.stopQuietly(); },
                [this] { bringToTooth(); }, [this] { ui_.help.shown = !ui_.help.shown; }}),
        shots_(o.shots.shots_s, o.shots.frame_every_s), end_(o.end, false, std::nullopt) {
    ui_.reduction.shown = o.reduction_map;
  }
  Result<SimulatorOutcome> run();

 private:
  // ---- set-up (simulator_setup.cpp)
  Status setUp();
  Status checkMode();
  Status loadPresetAndTask();
  Status loadTooth();
  Status loadDrill();
  Status loadMirror();
  // The task's first view (or --view, or buccal raised 30 degrees), widened to take in the mirror where
  // it starts; a fixed task view locks the mouse and keys out.
  Status placeCamera();
  Status setUpScript(const Pose& mirror_start);
  Result<PenPath> taskAttemptScript(Attempt attempt) const;  // the task's scripted preparation, careful or with a fault
  Status setUpPens();
  Status setUpPainter();
  void setUpPanel();
  Status recordingFolder();  // teacher mode without --out: a temporary folder for the sessions
  void showTask();           // the task's title, instructions and kind in the panel

  // ---- picks (simulator_picks.cpp)
  // After a new tooth or task: the surfaces rebuilt, the score cleared, the pens back at their
  // starts, and a new segment on the new tooth.
  Status restartOnNewTooth(const std::string& reason);
  Status pickTooth() override;    // the panel's tooth picker (ui_.tooth, ui_.level)
  Status pickTask() override;     // the panel's task picker (ui_.task)
  Status recordIdeal() override;  // teacher mode's "Record as ideal"

  // ---- segments (simulator_segments.cpp)
  Status startSegment() override;
  Status endSegment(const std::string& reason) override;
  bool segmentRunning() const override { return segments_.running(); }

  // ---- one frame's stages (simulator.cpp)
  Status frame();
  void readInput();                       // the window's events, a closed window, Ctrl-C
  FramePlan stepHaptics();                // lockstep: the loop up to this frame's time; what it draws
  void drainEdits();                      // the loop's voxel edits into the frame loop's copy
  Status updateSurfaces(const FramePlan& plan);  // edited bricks re-meshed, full detail filled in
  void showReadouts(const HapticState& state);   // ghost, force, pedal, devices, sound, haptic rate
  ui::PanelActions drawPanel(const FramePlan& plan);
  void timeFrame(Clock::time_point t0, const FramePlan& plan);
  Status applyEndRules(double t);
  Status endScript();                     // the script played out: recorded, ended, scored, last shot

  // ---- the scene (simulator_scene.cpp)
  render::FrameState frameState(const HapticState& state, VkExtent2D extent) const;
  Status drawFrame(const ShotSchedule::Due& due);
  // Where the tooth is on screen, for the score picture to stay off it; empty when it is behind the eye.
  PixelRect toothRect(VkExtent2D extent) const;
  // Pixels the scene moves left so that its centre is the middle of what the panel (and the controls
  // overlay on the left, while it shows) leave free: the tooth is never behind the overlay.
  int sceneShiftPx() const {
    if (!painter_->panel()) return 0;
    const int help_right = state_.help_rect.width > 0 ? state_.help_rect.x + state_.help_rect.width : 0;
    return (state_.panel_rect.width - help_right) / 2;
  }

  // ---- the panel's actions and the score (simulator_panel.cpp); drivePanel orders the calls
  Status handleActions(ui::PanelActions& actions);
  Status applyParams() override;
  void applyNormalMode() override;
  void applyPedal() override;
  Status teacherFolder() override;
  bool burDiffers() const override { return ui_.bur != model_.drill_name; }
  Status changeBur() override;
  bool builtinTooth() const override { return model_.tooth.builtin(); }
  void keepFileLevel() override;
  Status rebuildTooth(bool new_level) override;
  Status scoreNow() override;

  std::string outPath(const std::string& name) const { return (std::filesystem::path(o_.out) / name).string(); }
  void note(const std::string& text);
  // A warning: on stderr through warn(), as every command's, and on the panel's status line.
  void noteWarning(const std::string& text);
  Status finishRun(Status result);  // the loop stopped: segment ended, devices let go, sound written
  void fillOutcome();

  SimulatorOptions o_;
  SimulatorOutcome out_;
  bool headless_ = false;
  bool lockstep_ = false;

  SimRunModel model_;
  SimRunState state_;
  SimRunStats stats_;

  // The parts, one job each.
  DeviceRack rack_;
  std::unique_ptr<ui::PenInput> pens_;  // the mouse and keys move the virtual pens
  Segments segments_;
  RunSound sound_;
  render::OrbitCamera camera_;
  WindowInput input_;                     // the window's callbacks point here: it outlives the window
  std::unique_ptr<FramePainter> painter_;
  ShotSchedule shots_;
  ui::UiState ui_;                        // what the panel shows and edits
  std::unique_ptr<ui::PresetStore> presets_;
  EndRules end_;                          // when the run quits by itself
  TerminalProgress progress_;             // full detail filling in after the first frame
  // Wall time each frame gives the full copy's meshing while the first frames come in parts [ms]:
  // enough to finish a level-9 molar in a few seconds, little enough to keep the view moving.
  static constexpr double kDetailSliceMs = 40.0;

  // ---- the professional's ghost (simulator_ghost.cpp): drawn only, never in the haptic loop
  Status setUpGhost();                       // --ghost read (an error ends the run) and the panel's ghost state
  void restartGhost();                       // a segment starts: the ghost's task time from here
  void followGhost(const HapticState& state);  // this frame's ghost pose, loading it when first shown
  void showGhost(render::FrameState& fs) const;
  std::string ghostSource() const;           // --ghost, else the task's ideal session; empty: none
  Status loadGhost(const std::string& source);  // ghost_ read from `source`, its warnings noted
  std::optional<GhostDriver> ghost_;
  std::string ghost_failed_;                 // a source that did not load (not tried again)
  double ghost_t0_ = 0.0;                    // loop time at the segment's start [s]

  // ---- the student's help (simulator_help.cpp): the controls overlay, bring to tooth, guidance, scripted input
  Status setUpHelp();                        // --input read; the overlay's facts and first use; the guidance's source
  Status feedScriptedInput();                // the --input events due at this frame's time
  double secondsSinceStart() const;          // wall time since the run began [s]
  // The left button pressed (down) or let go in the middle of the panel widget `widget`, through
  // ImGui's next frame (scripted clicks: --input and --after-score-click); false when the widget
  // was not on the panel last frame.
  bool scriptClick(const std::string& widget, bool down);
  void bringToTooth();                       // B: the drill just over the professional's first contact
  void handleHelpActions(const ui::PanelActions& actions);  // Got it, the overlay's Bring, the guidance switch
  const GuidePath* segmentGuide();           // the guide the next segment starts with; null: unguided
  void showGuidePull(const HapticState& state, VkExtent2D extent);  // the overlay's arrow and bar
  const PenPath* professionalPenPath();      // the task's professional path, built on first use; null: none
  void helpNewTooth();                       // a new tooth or task: the professional's path and guide built again
  std::vector<ScriptedInput> inputs_;
  size_t next_input_ = 0;
  std::string click_widget_;                 // a scripted click's widget, let go next frame
  ui::WidgetRects rects_;                    // where the panel's widgets were last frame (scripted clicks)
  std::optional<PenPath> pro_pen_;
  bool pro_pen_tried_ = false;
  std::optional<GuidePath> panel_guide_;     // the panel's guide, from --guide or the professional's path
  bool panel_guide_tried_ = false;

  // ---- the student and the review after a score (simulator_review.cpp): records read, never written here
  void setUpStudent();                         // the student named or asked for, the picker's records
  void showRecords();                          // the outbox read again: the picker's attempts, the Score page's last ones
  // After a score: the review's buttons (or why each is off) and this attempt's parts.
  void prepareReview(const std::string& session_file, const std::string& no_session_reason,
                     const nlohmann::ordered_json& report);
  Status handleReview(const ui::ReviewActions& a);  // the Score page's buttons and the prompt's name
  Status reviewReplay(bool with_ghost);        // this attempt replayed in this window until Back
  Status retryGuided();                        // the uncut tooth again, the guide's spring on
  void clickAfterScore();                      // --after-score-click: the next widget clicked once it shows
  bool reviewHolds() const;                    // scripted clicks still to come: the run waits for them
  SimReviewState review_;

  // ---- the crown's reduction map (simulator_reduction.cpp): computed off this thread, never in the haptic loop
  Status refreshReductionMap(const FramePlan& plan);  // the switch read, a finished map shown, a new one started
  ReductionMapRefresh::Job reductionMapJob();         // copies of the teeth taken here, measured on the worker
  Status showReductionMap(const Result<ReductionMap>& map);
  Status hideReductionMap();                          // the switch off: the score's picture back, if any
  void reductionMapNewTooth(bool new_initial);        // a reset, a new level or tooth: the map starts again
  ReductionMapRefresh map_;
  std::shared_ptr<const ToothVolume> map_initial_;    // the uncut tooth, copied once per tooth for the jobs
  bool map_on_ = false;                               // the switch as last read (and the task a crown)
  bool map_timed_ = false;                            // the first map's time printed
};

}  // namespace dentsim::app
