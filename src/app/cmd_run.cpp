// `dentsim run`: the interactive simulator, in a window with haptic pens or the mouse as the pens, or headless with a pen script.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/data_folder.h"
#include "app/learning_cli.h"
#include "app/shared_options.h"
#include "app/simulator.h"
#include "sim/novice_paths.h"
#include "ui/course_list.h"

namespace dentsim::app {
namespace {

// The ranges of the loop-time options: a run ends within a day of loop time (kMaxLoopTimeS), and a
// lockstep frame holds between 1 ms and 1 s of it, so neither a frame nor the run can grow without bound.
constexpr double kMinFrameEveryS = 0.0;          // 0: no frame pictures [s]
constexpr double kMinFps = 1.0, kMaxFps = 1000.0;  // [frames/s]

// Options that the chosen mode cannot use, each refused with the reason (checked after parsing).
Status checkRunOptions(const SimulatorOptions& o, const CLI::App& cmd) {
  auto given = [&](const char* name) { return cmd.count(name) > 0; };
  const bool script = !o.pen_script.empty() || o.demo_script;
  const Status checks[] = {
      refuseOption(given("--pen-script") && o.demo_script, "--pen-script",
                   "--demo-script plays the task's own path; give one of the two"),
      refuseOption(given("--audio-out") && !o.sound.sound, "--audio-out", "--no-sound makes no sound to write"),
      refuseOption((given("--turbine-wav") || given("--cutting-wav")) && !o.sound.sound, "--turbine-wav/--cutting-wav",
                   "--no-sound plays no recording"),
      refuseOption((given("--turbine-wav") || given("--cutting-wav")) && o.frames.headless && o.sound.audio_out.empty(),
                   "--turbine-wav/--cutting-wav", "a headless run plays no sound; give --audio-out to render it to a WAV"),
      refuseOption(given("--recorded-rpm") && o.sound.turbine_wav.empty(), "--recorded-rpm",
                   "is the speed of a --turbine-wav recording; none is given"),
      refuseOption(given("--attempt") && !o.demo_script, "--attempt", "picks the scripted attempt of --demo-script"),
      refuseOption(given("--guide-stiffness") && o.guide.empty(), "--guide-stiffness", "is the spring of --guide; none is given"),
      refuseOption(given("--wander") && !script, "--wander", "moves a pen script's drill; give --pen-script or --demo-script"),
      refuseOption(given("--hand-stiffness") && !script && o.devices.drill_pen.rfind("script:", 0) != 0, "--hand-stiffness",
                   "is the hand holding a pen script; give --pen-script, --demo-script or --drill script:FILE"),
      refuseOption(given("--record-ideal-at-end") && !script, "--record-ideal-at-end",
                   "records when the pen script ends; give --pen-script or --demo-script"),
      refuseOption(given("--score-at-end") && !script, "--score-at-end",
                   "scores when the pen script ends; give --pen-script or --demo-script"),
      refuseOption(given("--exit-at-end") && !script, "--exit-at-end",
                   "quits when the pen script ends; give --pen-script or --demo-script"),
  };
  for (const Status& st : checks)
    if (!st) return st;
  if (!o.bur.empty())
    if (Status st = checkCatalogTool("--bur", o.bur, ToolUse::Bur); !st) return st;
  if (o.mirror_tool && !o.mirror_tool->empty())
    if (Status st = checkCatalogTool("--mirror-tool", *o.mirror_tool, ToolUse::Mirror); !st) return st;
  return Ok{};
}

// The file a pen's device reads, when it plays one ("script:FILE", "replay:FILE").
std::string penFile(const std::string& pen) {
  for (const char* prefix : {"script:", "replay:"})
    if (pen.rfind(prefix, 0) == 0) return pen.substr(std::string(prefix).size());
  return {};
}

// No file the run reads is one it writes, and an output folder's recording is kept unless --overwrite.
Status checkRunFiles(const SimulatorOptions& o, bool overwrite) {
  const std::vector<std::string> inputs = {o.tooth,       o.params,      o.task,
                                           o.pen_script,  o.guide,       o.ghost.session,
                                           o.sound.turbine_wav, o.sound.cutting_wav, o.devices.backends.falcon.firmware_path,
                                           penFile(o.devices.drill_pen), penFile(o.devices.mirror_pen)};
  std::vector<std::string> outputs = recordingOutputs(o.out);
  outputs.push_back(o.sound.audio_out);
  if (Status st = checkOutputsAreNotInputs(inputs, outputs); !st) return st;
  if (!o.out.empty())
    if (Status st = checkRecordingFolder(o.out, overwrite); !st) return st;
  return Ok{};
}

// What a run measured, for the terminal and docs/PERFORMANCE.md.
void printOutcome(const SimulatorOutcome& r) {
  std::printf("%s on %s: %llu frames (%llu drawn) in %.1f s; frame %.2f ms mean, %.2f ms p95 (%.1f frames/s); "
              "haptic %.0f steps/s (%llu steps); re-mesh %.2f ms mean; removed %.4f mm^3\n",
              r.windowed ? "window" : "headless", r.device.c_str(), static_cast<unsigned long long>(r.frames),
              static_cast<unsigned long long>(r.drawn), r.wall_s, r.frame_ms_mean, r.frame_ms_p95,
              r.frame_ms_mean > 0 ? 1000.0 / r.frame_ms_mean : 0.0, r.haptic_rate_hz,
              static_cast<unsigned long long>(r.haptic_steps), r.remesh_ms_mean, r.removed_mm3);
  if (r.score) std::printf("score %.2f\n", *r.score);
  else std::printf("not scored: %s\n", r.not_scored.c_str());
  for (const std::string& f : r.written) std::printf("wrote %s\n", f.c_str());
}

}  // namespace

void addRunCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<SimulatorOptions>();
  auto learning = std::make_shared<LearningCliOptions>();
  auto output = std::make_shared<OutputOptions>();
  CLI::App* cmd = root.add_subcommand("run", "The simulator: drill a tooth with the mouse (or a pen script) in a window, or headless to PNG frames");
  cmd->add_option("--tooth", o->tooth, "Tooth file (.dvol); default: the task's tooth (the built-in molar for the built-in tasks)");
  cmd->add_option("--level", o->level, "Octree level of the built-in molar; default: the task's (9 for the built-in tasks)")
      ->check(CLI::Range(6, 11));
  cmd->add_option("--params", o->params, "Parameter preset (.json); default: dentsim's defaults");
  cmd->add_option("--task", o->task, "Task scored: caries, cavity, another built-in task's name (class1_indirect) or a task file")
      ->capture_default_str();
  cmd->add_option("--course", o->course,
                  "Course folder: its .dvol teeth and .json tasks join the built-in ones in the panel's pickers "
                  "(default: assets/tasks under the current folder, when it exists, else the installed course, "
                  "share/dentsim/tasks beside the binary's bin/)");
  cmd->add_flag("--teacher", o->teacher,
                "Teacher mode: the panel's Record as ideal makes a segment the task file's ideal "
                "(sessions go to a temporary folder without --out)");
  cmd->add_flag("--record-ideal-at-end", o->record_ideal_at_end,
                "With --teacher and a pen script: when the script ends, record the segment as the task file's ideal");
  cmd->add_option("--bur", o->bur, "The bur on the drill pen; default: the task's");
  cmd->add_option_function<std::string>("--mirror-tool", [o](const std::string& name) { o->mirror_tool = name; },
                                        "The mirror tool; default: the task's (mirror_size4 for the built-in tasks)");
  cmd->add_option("--drill", o->devices.drill_pen,
                  "The drill's pen: virtual, falcon[:N], openhaptics[:NAME], script:FILE or replay:FILE "
                  "(`dentsim devices` lists them); default: the pen script, else virtual");
  cmd->add_option("--mirror", o->devices.mirror_pen, "The mirror's pen (as --drill), or 'none' for no mirror");
  cmd->add_option("--pedal", o->devices.pedal, "The foot pedal: none, hid[:N], hid:VVVV:PPPP[,layout] or hid:/dev/hidrawN")
      ->capture_default_str();
  cmd->add_option("--falcon-firmware", o->devices.backends.falcon.firmware_path, "The Novint Falcon's firmware file (you supply it)");
  cmd->add_option("--reach", o->devices.backends.reach_mm, "How much of the scene a hardware pen's workspace spans [mm]")
      ->check(finiteIn(1.0, 1000.0, "mm"))->capture_default_str();
  cmd->add_option("--audio-out", o->sound.audio_out, "Render the sound offline to this WAV file (headless too) instead of playing it");
  cmd->add_flag("!--no-sound", o->sound.sound, "No sound at all");
  cmd->add_option("--turbine-wav", o->sound.turbine_wav, "A turbine recording (WAV) to play instead of the synthesized whine");
  cmd->add_option("--cutting-wav", o->sound.cutting_wav, "A cutting recording (WAV) to play instead of the synthesized noise");
  cmd->add_option("--recorded-rpm", o->sound.recorded_rpm, "The turbine recording's speed [1/min]")
      ->check(finiteIn(100.0, 1e6, "1/min"))->capture_default_str();
  cmd->add_option("--pen-script", o->pen_script, "Pen path (CSV or JSON) that both pens play, instead of the mouse");
  cmd->add_flag("--demo-script", o->demo_script,
                "Play the task's scripted preparation (caries removal or class I cavity), the mirror held beside the tooth");
  cmd->add_option("--attempt", o->attempt, "With --demo-script: the careful one or one with a fault: " + attemptNames())
      ->check(CLI::IsMember(attemptNameList()))
      ->capture_default_str();
  cmd->add_option("--guide", o->guide,
                  "A professional's session (.dses): a spring pulls the drill toward its path (haptic guidance)");
  cmd->add_option("--input", o->input,
                  "Scripted window input T EVENT (repeatable): key:NAME, wheel:STEPS, drag:DX,DY or click:WIDGET "
                  "at time T [s] (frames / fps in lockstep), through the same handlers as the mouse and keys (docs/SIMULATOR.md)");
  cmd->add_option("--help-overlay", o->help, "The controls overlay at the start: auto (first use with the mouse), show or hide")
      ->check(CLI::IsMember({"auto", "show", "hide"}))
      ->capture_default_str();
  cmd->add_option("--guide-stiffness", o->guide_settings.stiffness_n_per_mm, "The guide's spring [N/mm]")
      ->check(finiteIn(0.01, 10.0, "N/mm"))
      ->capture_default_str();
  cmd->add_option_function<double>(
         "--hand-stiffness", [o](double k) { o->devices.script_hand = HandSettings{k, HandSettings{}.lag_s}; },
         "A pen script is held by a hand of this stiffness that gives way to the rendered force [N/mm]; default: rigid")
      ->check(finiteIn(0.05, 100.0, "N/mm"));
  cmd->add_option("--wander", o->wander_mm,
                  "The pen script's drill wanders sideways up to this far, off its path and back (a shaky hand) [mm]")
      ->check(finiteIn(0.0, 5.0, "mm"));
  cmd->add_flag("--headless", o->frames.headless, "No window: frames go offscreen, to PNG (also when no display answers)");
  cmd->add_option("--width", o->frames.width, "Window or frame width [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  cmd->add_option("--height", o->frames.height, "Window or frame height [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  addOutputOptions(*cmd, output.get(), {"the session, the teeth, the score, screenshots and frames", ""});
  cmd->add_option("--frame-every", o->shots.frame_every_s, "Also write frame-N.png every so many seconds of loop time [s]")
      ->check(finiteIn(kMinFrameEveryS, kMaxLoopTimeS, "s"));
  cmd->add_option("--exit-after", o->end.exit_after_s, "Quit at this loop time, at most 24 h [s]")
      ->check(finiteIn(0.0, kMaxLoopTimeS, "s"));
  cmd->add_flag("--lockstep", o->lockstep, "Step the haptic loop from the frame loop (reproducible frames; always when headless)");
  cmd->add_option("--fps", o->fps, "Loop time per frame in lockstep [frames/s]")
      ->check(finiteIn(kMinFps, kMaxFps, "frames/s"))
      ->capture_default_str();
  cmd->add_option("--idle-latency-us", o->idle_latency_us,
                  "While the haptic thread runs, ask that idle CPUs wake within this many us "
                  "(/dev/cpu_dma_latency; costs power); -1: do not ask")
      ->check(CLI::Range(-1, 1000000))
      ->capture_default_str();
  cmd->add_flag("!--no-ui", o->frames.ui, "Hide the parameter window and the overlay");
  cmd->add_option("--view", o->view, "First camera view: occlusal, buccal, lingual, mesial or distal (default: the task's, else buccal)");
  addDrawingOptions(*cmd, &o->frames.detail_pixels, &o->frames.mesher);
  cmd->add_option_function<bool>(
      "--progressive", [o](bool on) { o->frames.progressive = on; },
      "First frame from the coarse copies, full detail filling in over the next frames (default: in a window, not "
      "headless)");
  cmd->add_flag("!--no-vsync", o->frames.vsync, "Present as fast as frames come (frame-rate measurements)");
  cmd->add_flag("--score-at-end", o->score_at_end, "Score the cut when the pen script ends");
  cmd->add_flag("--exit-at-end", o->end.exit_at_end, "Quit one frame after the pen script ends, windowed too");
  cmd->add_option("--device", o->frames.device, "Vulkan device index or name part");
  cmd->add_option("--ghost", o->ghost.session,
                  "A professional's session (.dses): its drill and mirror show translucent beside yours "
                  "(the panel's View page hides it); default: none, or the task's recorded ideal when the panel shows it");
  cmd->add_option("--ghost-follow", o->ghost.follow,
                  "How the ghost moves: time (the professional's pose at your task time) or nearest "
                  "(standing where the professional's bur came nearest yours)")
      ->check(CLI::IsMember({"time", "nearest"}))
      ->capture_default_str();
  cmd->add_flag("--reduction-map", o->reduction_map,
                "A crown task: show the reduction map from the start (the View page's switch): the prepared surface "
                "green within the task's band, blue where more must come off, red where too much did");
  cmd->add_option("--after-score-click", o->review.presses,
                  "After the score shows, click these panel widgets in turn, each once it is on screen (review.replay, "
                  "review.ghost, review.guided; tests and demonstrations); repeatable")
      ->check([](const std::string& w) { return w.empty() ? std::string("an empty widget key") : std::string(); });
  cmd->add_option("--review-shot", o->review.shots_s,
                  "A review's replay writes a screenshot at this replay time into <out>/review-N/ [s]; repeatable")
      ->check(finiteIn(0.0, kMaxLoopTimeS, "s"));
  // --course is the folder the pickers list, so the learning records' course id is --course-id here.
  addLearningOptions(cmd, *learning, "--course-id");
  cmd->callback([o, learning, output, cmd, &action] {
    // A student's start: a course named, no task: the course's first task, the student's records,
    // and the name asked for when none is known (docs/SIMULATOR.md, "A student's start").
    const bool student_start = cmd->count("--course") > 0 && cmd->count("--task") == 0;
    o->out = output->out;
    o->shots.shots_s = output->shots_s;
    if (cmd->count("--course") == 0) {
      std::error_code ec;
      o->course = ui::defaultCourseFolder(std::filesystem::current_path(ec).string());
      // Outside a source tree: the course an installed dentsim brings (share/dentsim/tasks).
      if (o->course.empty()) o->course = installedCourseFolder(executableFolder());
    }
    if (o->record_ideal_at_end && !o->teacher) throw CLI::ValidationError("--record-ideal-at-end", "needs --teacher");
    Status usable = checkOutputOptions(*output, *cmd);
    if (usable) usable = checkRunOptions(*o, *cmd);
    action = [o, learning, output, usable, student_start] {
      if (!usable) return fail(usable.message());
      if (student_start)
        if (const std::string first = ui::firstCourseTask(ui::listCourse(o->course)); !first.empty()) o->task = first;
      if (Status st = checkRunFiles(*o, output->overwrite); !st) return fail(st.message());
      if (Status st = checkLearningOptions(*learning); !st) return fail(st.message());
      if (auto learner = learnerSettings(*learning)) {
        o->student.id = learner->learner.student;
        o->student.outbox = learner->outbox;
        o->student.course_id = learner->learner.course;
        o->student.activity_base = learner->learner.activity_base;
        o->student.config_path = learner->config_path;
        o->student.student_start = student_start;
      }
      o->on_scored = [learning](const Task& task, nlohmann::ordered_json& report, const std::string& session,
                                const std::string& final_file) { recordAttemptOrWarn(*learning, task, report, session, final_file); };
      auto r = runSimulator(*o);
      if (!r) return fail(r.message());
      printOutcome(*r);
      // After the run, never inside it: a dead LRS must not stall the frame loop.
      if (Status st = sendPendingIfConfigured(*learning); !st) return fail(st.message());
      return 0;
    };
  });
}

}  // namespace dentsim::app
