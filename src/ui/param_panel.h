// The parameter window (the paper's Figure 16) and the frame overlay: Dear ImGui widgets over UiState, returning what the user asked for.
//
// Contents
//   1. UiState: what the panel shows and edits (the app owns it and fills the read-only parts)
//   2. PanelActions: what one frame of the panel asks the app to do
//   3. Entry points: drawParamPanel, drawOverlay, applyPresetActions
//
// Immediate mode: call the draw functions once per frame between ImGuiLayer::newFrame and
// ImGuiLayer::render (or between ImGui::NewFrame and ImGui::Render with any ImGui context). The panel
// edits UiState in place and never touches the simulation itself; the app reads PanelActions and
// pushes the changed set to the haptic loop and the renderer in the same frame, so a change applies
// at once, to force and to colour. Every widget clamps to a sub-range of what parsePreset
// accepts, so the panel can never produce a set that would not save.
//
// Windows and where they sit (fixed first positions, no .ini file, so frames are reproducible):
//   "Parameters"      right edge, full height, 380 px wide. The run's buttons (Start, Stop, Reset,
//                     Score) sit on top; below them one tab per page, each of which fits in a window
//                     800 px high without scrolling: Task (tooth and task pickers, the task's
//                     instructions, teacher mode), Tissues, Tools (bur, turbine, sound), View
//                     (normals, voxel level, the ghost, a crown task's reduction map), Presets
//                     (and the advanced section), Score (with a score); the status line last. A
//                     slider shows its value beside its track, never under the grab.
//   "##overlay"       top-left, takes no input: frame time, haptic rate, re-mesh time, triangles,
//                     rpm, force gauge, contact
//   "Score picture"   shown with a score, beside the tooth (UiState::keep_clear), never over it: no
//                     background, so the renderer's red/blue picture drawn in
//                     PanelActions::score_image_rect before the ImGui pass shows through
//   "Reduction map"   the same window holding the crown's reduction map instead, while the app
//                     says it is on screen (ReductionMapView::on_screen)
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/pixel_rect.h"
#include "model/tool_generator.h"
#include "render/look_params.h"
#include "sim/sim_params.h"
#include "ui/course_list.h"
#include "ui/preset_store.h"
#include "ui/review_state.h"

namespace dentsim::ui {

// ---- 1. state ----------------------------------------------------------------------------------------

enum class RunState { Idle, Running, Stopped };

// One line of the score screen ("over-cut", "0.42 mm^3").
struct ScoreRow {
  std::string label;
  std::string value;
};

struct ScoreSummary {
  bool valid = false;            // false before a task has been scored
  double total = 0.0;            // [0..total_max]
  double total_max = 100.0;      // 100, or less when parts were not scored (no session)
  std::vector<ScoreRow> rows;    // sub-scores and volumes, in display order
  int image_width = 0;           // the red/blue picture's size [px]; the panel keeps its aspect
  int image_height = 0;
};

// The crown preparation's reduction map (View page, crown tasks only; app/reduction_map.h): the
// app paints the prepared surface by its reduction and shows it in the picture window.
struct ReductionMapView {
  bool available = false;        // set by the app: the task is a crown preparation
  bool shown = false;            // the checkbox "Reduction map"
  bool on_screen = false;        // set by the app: the picture window holds the map, not the score picture
  std::string legend;            // set by the app: the task's bands ("occlusal 1.5-2.0 mm, axial 1.0-1.5 mm")
  std::string status;            // set by the app: the map's shares and its time to measure, or why there is none
  int image_width = 0;           // the map's size [px]; the picture window keeps its aspect
  int image_height = 0;
};

// The controls overlay (ui/controls_help.h): what the student is told about the pen in use, the
// task and the bur, on first use and from the Help button or F1.
enum class DrillInput { Mouse, HapticPen, Script };
struct ControlsHelp {
  bool shown = false;            // on screen; the app sets it on first use, the panel's buttons and F1 toggle it
  DrillInput input = DrillInput::Mouse;  // set by the app: what moves the drill
  std::string device;            // set by the app: the drill's pen as the student knows it ("Touch (OpenHaptics)")
  std::string bur;               // set by the app: the bur on the drill, and what it is ("round_bur_010: round, 1.0 mm")
  bool bring_available = false;  // set by the app: the task has a professional's path for "bring to tooth"
};

// Haptic guidance on the panel (Tools page) and its pull on the overlay. A session records its
// guide in its header, so the switch and the stiffness apply from the next segment on (Start or
// Reset), never to the running one: a guided session replays to the same forces.
struct GuidanceView {
  bool available = false;        // set by the app: a professional's path to follow (--guide, else the task's ideal)
  std::string source;            // set by the app: that path's session, or why there is none
  bool on = false;               // the switch
  double stiffness_n_per_mm = 1.0;  // the slider [N/mm]
  bool active = false;           // set by the app: the running segment is guided
  double pull_n = 0.0;           // set by the app: the guide's force this frame [N]
  double max_n = 2.0;            // set by the app: the guide's cap [N]
  float tip_px[2] = {0, 0};      // set by the app: the bur's tip on screen [px]
  float pull_px[2] = {0, 0};     // set by the app: the pull's direction on screen, unit (0, 0: along the view)
};

// Measured by the app each frame; shown by drawOverlay.
struct OverlayStats {
  double frame_ms = 0.0;        // last frame's CPU time [ms]
  double haptic_rate_hz = 0.0;  // haptic loops per second, measured [Hz]
  double remesh_ms = 0.0;       // last incremental re-mesh [ms]
  uint64_t triangles = 0;       // tooth triangles drawn last frame (main and mirror pass)
  double detail_progress = 1.0; // share of the full copy meshed while the first frames come in parts [0..1]
};

// Contact shows as a gauge since a mouse-driven pen has no force to feel.
struct ForceGauge {
  double force_n = 0.0;      // drill force magnitude [N]
  double max_force_n = 8.0;  // the gauge's full scale, the device's clamp [N]
  bool contact = false;      // the bur touches tissue
};

// The sound's controls; the app applies them to the sound engine each frame.
struct SoundControls {
  double volume = 0.8;     // [0, 1]
  bool mute = false;
  std::string output;      // where the sound goes, one line ("OpenAL Soft", "sound.wav", "no sound device: silent")
};

struct UiState {
  SimParams params = defaultSimParams();   // the working set the panel edits, tactile half
  LookParams looks = defaultLookParams();  // and visual half (one preset with params)
  std::string bur = kDefaultBur;           // the drill's tool name (toolCatalog / params.burs)
  double turbine_speed = 0.0;              // [0..1] of params.turbine.max_rpm
  bool pedal_present = false;              // false: the slider, PageUp/PageDown and the wheel set the speed
  int level = 9;                           // octree level of the tooth, kMinLevel..kMaxLevel
  // The pickers (set by the app; the panel edits the choices and raises tooth_changed, task_changed).
  CourseList course;                       // the teeth and tasks offered (listCourse)
  std::string tooth;                       // the tooth in use: a volume file, empty for the built-in molar at `level`
  std::string tooth_path;                  // the "open" field: any .dvol by its path
  std::string tooth_error;                 // why the tooth last picked did not load; empty when it did
  std::string task = "caries";             // the task in use: a TaskChoice::source (a built-in name or a file)
  std::string task_title;                  // the task in use's title, and what it asks of the student
  std::string task_instructions;
  std::string task_error;                  // why the task last picked did not start; empty when it did
  // Teacher mode: "Record as ideal" makes the current segment the task file's ideal.
  bool teacher = false;
  bool task_is_file = false;               // the task in use is a file (a built-in one cannot take an ideal)
  bool segment_recorded = false;           // the current segment is being recorded to a session file
  std::string ideal_status;                // the last recording's result or error; empty: none yet
  std::vector<std::string> presets{kDefaultPresetName};  // PresetStore::list()
  std::string selected_preset = kDefaultPresetName;
  std::string save_name;                   // the "save as" field
  RunState run_state = RunState::Idle;     // set by the app
  ScoreSummary score;                      // set by the app after a score
  OverlayStats stats;                      // set by the app each frame
  ForceGauge force;                        // set by the app each frame
  SoundControls sound;                     // volume and mute edited here; output set by the app
  std::string status;                      // last error or notice, one line ("preset 'soft' saved")
  PixelRect keep_clear;                    // where the tooth is on screen: the score picture stays off it; empty: anywhere
  // The professional's ghost (View page): a session's tools drawn translucent beside the student's.
  bool ghost_available = false;            // set by the app: --ghost was given, or the task has a recorded ideal
  bool ghost_shown = false;                // the checkbox
  bool ghost_nearest = false;              // false: the ghost follows the task time; true: it stands nearest the bur
  float ghost_opacity = 0.4f;              // [0.1, 0.9]
  std::string ghost_source;                // set by the app: the session the ghost shows, or why none
  ReductionMapView reduction;              // the crown preparation's live reduction map
  StudentView student;                     // the student named, or the first-run prompt (ui/review_panel.h)
  ReviewView review;                       // the Score page's review: replay, ghost, guided retry, last attempts
  ControlsHelp help;                       // the controls overlay
  GuidanceView guidance;                   // haptic guidance's switch, slider and pull
};

// ---- 2. actions --------------------------------------------------------------------------------------


struct PanelActions {
  bool params_changed = false;       // any field of UiState::params or UiState::looks
  bool bur_changed = false;          // UiState::bur
  bool speed_changed = false;        // UiState::turbine_speed (no pedal only)
  bool level_changed = false;        // UiState::level: rebuild the tooth
  bool normal_mode_changed = false;  // looks.view.normals (params_changed too): re-mesh
  bool tooth_changed = false;        // UiState::tooth (and level, for the built-in molar): restart on it
  bool task_changed = false;         // UiState::task: start it (its tooth, level, tools and view)
  bool record_ideal = false;         // teacher mode: make the current segment the task's ideal
  bool sound_changed = false;        // UiState::sound volume or mute
  bool start = false, stop = false, reset = false, score = false;
  bool help_closed = false;          // the student closed the controls overlay ("Got it"): not shown on its own again
  bool bring_to_tooth = false;       // the overlay's "Bring the bur to the tooth" (as the B key)
  bool guidance_changed = false;     // UiState::guidance on or stiffness: applies from the next segment
  std::string load_preset;           // a preset to load; empty: none
  std::string save_preset;           // save params under this name; empty: none
  PixelRect score_image_rect;        // where the renderer draws the score's picture or the reduction map; empty: nowhere
  PixelRect panel_rect;              // where the "Parameters" window is this frame
  PixelRect help_rect;               // where the "Controls" window is this frame; empty: not shown
  ReviewActions review;              // the Score page's review buttons and the name prompt (ui/review_state.h)
};

// ---- 3. entry points ---------------------------------------------------------------------------------

// Where drawParamPanel laid out each editable widget this frame (a labelled widget's frame without
// its label: a slider's track, a combo's box), by key (for tests and tutorials):
// "tissues.<tissue>.<field>" and "looks.<tissue>.<field>" (field names as in the preset JSON; the
// colour pickers are "looks.<tissue>.ambient", ".diffuse", ".specular"), "tab.<tissue>", "bur",
// "bur.cutting_ability", "turbine.speed", "turbine.max_rpm", "view.normal_neighbours.<8|64|216>",
// "level", "tooth", "tooth_path", "open_tooth", "task", "teacher", "record_ideal", "start", "stop",
// "reset", "score", "preset", "load", "save_name", "save", "ghost", "ghost.follow.<time|nearest>",
// "ghost.opacity", "reduction_map", "help" (the run buttons' Help), "help.close", "help.bring", "guidance",
// "guidance.stiffness", the pages' tabs "page.<task|tissues|tools|
// view|presets|score>", the advanced section's header "section.advanced", the pickers' open lists'
// entries "tooth.item.<i>" and "task.item.<i>", and beside each slider its value, "value.<the
// slider's key>".
struct WidgetRect {
  float min_x = 0, min_y = 0, max_x = 0, max_y = 0;  // ImGui screen coordinates [px]
};
using WidgetRects = std::map<std::string, WidgetRect>;

// Draws the "Parameters" window (and "Score picture" when state.score.valid). Needs a current ImGui
// context inside a frame. `rects`, when given, receives the widgets' rectangles.
PanelActions drawParamPanel(UiState& state, WidgetRects* rects = nullptr);

// Draws the overlay in the top-left corner; it takes no mouse input.
void drawOverlay(const UiState& state);

// Carries out the preset requests of `actions` with `store`: a load replaces state.params and
// state.looks (and sets actions.params_changed, and normal_mode_changed when the normals differ), a
// save writes both as one file and refreshes state.presets. Either way state.status tells the user what happened, error or notice.
void applyPresetActions(PanelActions& actions, const PresetStore& store, UiState& state);

}  // namespace dentsim::ui
