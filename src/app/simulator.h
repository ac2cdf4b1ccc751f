// The interactive simulator behind `dentsim run` and the windowed `dentsim demo`: window or offscreen frames, the haptic loop, the pens, the parameter window.
//
// Threads. The haptic loop runs on its own real-time thread and never waits for this one; the frame
// loop (the calling thread) drains the loop's voxel edits into its own copy of the tooth, re-meshes
// the changed bricks on the GPU, and draws the latest haptic state. Headless, or with `lockstep`,
// the frame loop steps the haptic loop itself, so that frame k shows exactly loop time k / fps:
// those frames are reproducible, and headless frames equal windowed ones for the same state.
//
// Segments. A session is recorded from Start to Stop (or the end): app/segments.h.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/device_rack.h"
#include "app/run_sound.h"
#include "app/sim_end_rules.h"
#include "core/result.h"
#include "gpu/mesher_kind.h"
#include "eval/task.h"
#include "sim/guide_spring.h"

namespace dentsim::app {

// How the frames are made: in a window or offscreen, their size, the device and the detail drawn.
struct SimFrameOptions {
  bool headless = false;                // offscreen frames, no window (also when no display answers)
  int width = 1280, height = 800;       // window or frame size [px]
  bool vsync = true;                    // windowed: wait for the display's refresh
  bool ui = true;                       // the parameter window and the overlay
  std::string device;                   // Vulkan device index or name part; empty: the best
  // Screen-sized detail (docs/MESHING.md): each region drawn from the coarsest copy of the tooth
  // within this many pixels of error; 0 draws everything at full detail (the path before it).
  float detail_pixels = 1.0f;
  gpu::MesherKind mesher = gpu::MesherKind::Auto;  // the tooth's mesher: the kernel, CPU threads, or what suits the device
  // The first frame comes from the coarse copies and full detail fills in around the view over the
  // next frames; false meshes everything before the first frame. Unset: on in a window, off headless
  // (so that a headless run's pictures never depend on how fast the machine meshes).
  std::optional<bool> progressive;
};

// The pictures written into `out` while the run goes (app/screenshots.h).
struct SimShotOptions {
  std::vector<double> shots_s;          // loop times of screenshots (shot-N.png and shot-N.json) [s]
  double frame_every_s = 0.0;           // also write frame-N.png every so much loop time (0: none) [s]
};

// The professional's ghost (docs/SIMULATOR.md): a session's drill and mirror drawn translucent
// beside the student's, never in the haptic loop.
struct SimGhostOptions {
  std::string session;                  // the professional's session (.dses); empty: the task's recorded ideal, if the panel shows it
  std::string follow = "time";          // "time": the pose at the student's task time; "nearest": nearest the student's bur
};

// The student at the simulator (docs/SIMULATOR.md, "A student's start"): whose learning records the
// task picker and the Score page show, read from which outbox, and where a name typed at the
// first-run prompt is kept. The commands fill it from app/learning_cli.h's learnerSettings.
struct SimStudentOptions {
  std::string id;                       // the student's account name; empty: nobody named
  std::string outbox;                   // the learning records' outbox read for the records; empty: none shown
  std::string course_id = "builtin";    // the records' course id
  std::string activity_base;            // the activity IRIs' base; empty: eval/learning_record.h's default
  std::string config_path;              // the learning config file, where the prompt keeps the name
  // A student's start (a course named, no task): the course's tasks with the records on the
  // terminal, and the window asks the name when nobody is named.
  bool student_start = false;
};

// The review after a score, scripted (tests and demonstrations; docs/SIMULATOR.md, "After the score").
struct SimReviewOptions {
  // Panel buttons pressed in turn by their widget keys (ui/param_panel.h WidgetRects: "score",
  // "review.replay", "review.ghost", ...): each is clicked through ImGui once it is on screen.
  std::vector<std::string> presses;
  std::vector<double> shots_s;          // screenshots of a review's replay at these replay times, in <out>/review-N/ [s]
};

struct SimulatorOptions {
  std::string tooth;                    // a tooth file (.dvol); empty: the task's tooth
  int level = 0;                        // octree level of the built-in molar; 0: the task's
  std::string params;                   // a preset file; empty: dentsim's defaults
  std::string task = "caries";          // the task scored ("caries", "cavity", another built-in task's name or a task file)
  std::string course;                   // the folder whose teeth (.dvol) and tasks (.json) the panel's pickers list; empty: the built-in ones
  bool teacher = false;                 // teacher mode from the start: "Record as ideal" (sessions go to a temporary folder without --out)
  bool record_ideal_at_end = false;     // teacher mode: when the pen script ends, Record as ideal (as the panel's button does)
  std::string bur;                      // the bur on the drill pen; empty: the task's
  std::optional<std::string> mirror_tool;    // the mirror tool; none: the task's; empty: no mirror
  std::string pen_script;               // a pen path (CSV or JSON) both pens play; empty: mouse and keys
  DeviceRackOptions devices;            // the pens, the pedal and their options (app/device_rack.h)
  // Sound (docs/SOUND.md): played live in a window; `sound.audio_out` renders it offline to a WAV
  // file (headless too) through OpenAL's loopback device instead.
  RunSoundOptions sound;
  double wander_mm = 0.0;               // the script's drill wanders sideways this far (sim/novice_paths.h wanderingPath) [mm]
  std::string guide;                    // a professional's session whose path a spring pulls the drill toward; empty: none
  GuideSettings guide_settings;         // that spring (sim/guide_spring.h)
  std::vector<std::pair<double, std::string>> input;  // --input: window events at loop times (app/scripted_input.h)
  std::string help = "auto";            // --help-overlay: the controls overlay "auto" (first use with the mouse), "show" or "hide"
  bool demo_script = false;             // the task's scripted preparation (caries removal or class I), the mirror held distally
  std::string attempt = "expert";       // with demo_script: the careful one, or one with a fault (sim/novice_paths.h)
  SimFrameOptions frames;               // window or offscreen, size, device, detail
  std::string out;                      // folder for the session, teeth, screenshots and frames; empty: none
  SimShotOptions shots;                 // screenshots and frame pictures in `out`
  SimEndOptions end;                    // when the run quits by itself (app/sim_end_rules.h)
  bool lockstep = false;                // the frame loop steps the haptic loop (always when headless)
  int idle_latency_us = 0;              // while the loop's thread runs, idle CPUs wake within this [us]; < 0: not asked
  double fps = 30.0;                    // loop time per frame in lockstep [frames/s]
  std::string view;                     // the first camera view (occlusal, buccal, lingual, mesial, distal); empty: the task's, else buccal
  bool score_at_end = false;            // score the cut when the script ends, write score files, show it
  // Called with every cut the run scores (at the script's end or by the panel's Score button): the
  // task, the score report, the session holding the whole cut (empty: none) and the final tooth
  // file (empty: not saved). The commands hand it app/learning_cli.h's recordAttempt. The hook may
  // add the learning record's "statement_id" to the report; score.json is then written again with it.
  std::function<void(const Task&, nlohmann::ordered_json& report, const std::string& session_file,
                     const std::string& final_file)>
      on_scored;
  SimGhostOptions ghost;                // the professional's ghost
  bool reduction_map = false;           // a crown task's reduction map shown from the start (the View page's switch)
  SimStudentOptions student;            // the student's records and the first-run prompt
  SimReviewOptions review;              // the review's scripted presses and screenshots
};

struct SimulatorOutcome {
  bool windowed = false;
  std::string device;                   // the Vulkan device that drew
  uint64_t frames = 0;                  // frames of loop time (lockstep) or drawn (windowed)
  uint64_t drawn = 0;                   // frames drawn (headless draws only what it writes)
  double wall_s = 0.0;
  // Frame times [ms]: windowed, from one frame's start to the next's (what the student sees);
  // headless, each drawn frame's own time (re-mesh, panel, draw, wait), without the haptic steps.
  double frame_ms_mean = 0.0;
  double frame_ms_p50 = 0.0;
  double frame_ms_p95 = 0.0;
  double haptic_rate_hz = 0.0;          // haptic steps per wall second from the first segment's start
  uint64_t haptic_steps = 0;
  double remesh_ms_mean = 0.0;          // incremental re-mesh per frame that had edits [ms]
  uint64_t triangles = 0;               // the tooth's full-copy surface at the end
  double triangles_drawn_mean = 0.0;    // tooth triangles drawn per drawn frame, both passes
  double first_frame_s = 0.0;           // wall time from the start of the run to the first frame drawn [s]
  double full_detail_s = 0.0;           // ... to the frame after which the full copy was whole [s]
  double removed_mm3 = 0.0;
  std::vector<std::string> written;     // files written, in order, each one on disk when the run returns
  std::optional<double> score;          // the last score made, of the tooth as the run left it
  std::string not_scored;               // with no score: why ("the window was closed before the script ended")
};

// Runs until the window closes, exit_after_s, or the script's end (see the options). Errors are
// one line: a bad option, a tooth or preset that does not load, no Vulkan device, a device lost.
Result<SimulatorOutcome> runSimulator(const SimulatorOptions& options);

}  // namespace dentsim::app
