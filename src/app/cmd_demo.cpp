// `dentsim demo [--headless] --out DIR`: the scripted pen removes the built-in molar's caries while the session is recorded, then the cut is scored; shown in the window where there is a display.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/learning_cli.h"
#include "app/mesh_output.h"
#include "app/shared_options.h"
#include "eval/task_tooth.h"
#include "eval/cut_score.h"
#include "app/simulator.h"
#include "gpu/context.h"
#include "io/session_file.h"
#include "model/tool_generator.h"
#include "sim/builtin_tooth.h"
#include "sim/novice_paths.h"
#include "sim/session_run.h"
#include "ui/preset.h"
#include "ui/window.h"
#include "volume/surface_mesher.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim::app {
namespace {

constexpr double kScoreScreenS = 4.0;  // how long the windowed demo shows its score before it closes [s]

struct DemoOptions {
  OutputOptions output;              // --out (default dentsim-demo), --overwrite, --shot (default: one at 1 s)
  int level = 9;                     // octree level of the molar
  bool headless = false;             // no window: frames offscreen (also when no display answers)
  bool realtime = false;             // headless without a Vulkan device: pace the loop at its rate
  std::string params;                // a preset (.json); default: dentsim's defaults
  double exit_after_s = 0.0;         // windowed: close at this loop time (0: after the score screen, or with --stay when the user closes it)
  bool stay = false;                 // windowed: keep the window open after the score screen until the user closes it
  int width = 1280, height = 800;    // window or frame size [px]
  std::string mirror = kDefaultMirror;  // the mirror the script holds beside the tooth; "none": none
  bool sound = true;                 // the window plays it; headless, it goes to sound.wav
  std::string attempt = "expert";    // the careful removal, or one with a fault (sim/novice_paths.h)
  LearningCliOptions learning;       // the attempt's learning record, when a student is named
  float detail_pixels = 1.0f;        // screen-sized detail's largest error [px]; 0: full detail everywhere
  gpu::MesherKind mesher = gpu::MesherKind::Auto;  // who meshes the tooth
};

// Options that cannot apply together, each refused with the reason (checked after parsing).
Status checkDemoOptions(const DemoOptions& o, const CLI::App& cmd) {
  if (Status st = checkOutputOptions(o.output, cmd); !st) return st;
  if (Status st = refuseOption(o.stay && o.headless, "--stay", "keeps a window open; --headless opens none"); !st) return st;
  if (Status st = refuseOption(cmd.count("--exit-after") > 0 && o.stay, "--exit-after",
                               "closes the window at a loop time; --stay keeps it open until you close it");
      !st)
    return st;
  if (o.mirror != "none")
    if (Status st = checkCatalogTool("--mirror", o.mirror, ToolUse::Mirror); !st) return st;
  return Ok{};
}

// The final tooth as a mesh, beside the other files: what a reader opens in any 3-D viewer.
int writeFinalMesh(const std::string& out, const ToothVolume& tooth) {
  SurfaceOptions mo;
  auto surface = meshVolumeCpu(tooth, mo);
  if (!surface) return fail(surface.message());
  const std::string mesh_path = (std::filesystem::path(out) / "final.ply").string();
  if (Status st = writeSurface(mesh_path, MeshFormat::Ply, *surface, tooth.frame, "demo final tooth"); !st) return fail(st.message());
  return 0;
}

// Without any Vulkan device: the same scripted drilling and score on the CPU, with no frames.
int runCpuDemo(const DemoOptions& o);

int runDemo(const DemoOptions& o) {
  namespace fs = std::filesystem;
  if (Status st = checkLearningOptions(o.learning); !st) return fail(st.message());
  if (Status st = checkOutputsAreNotInputs({o.params}, recordingOutputs(o.output.out)); !st) return fail(st.message());
  if (Status st = checkRecordingFolder(o.output.out, o.output.overwrite); !st) return fail(st.message());
  std::error_code ec;
  fs::create_directories(o.output.out, ec);
  if (ec) return fail(o.output.out + ": cannot create the output folder: " + ec.message());

  // The simulator shows it: live in a window, or headless in lockstep, writing a few frames.
  SimulatorOptions so;
  so.level = o.level;
  so.params = o.params;
  so.task = "caries";
  so.demo_script = true;
  so.attempt = o.attempt;
  so.mirror_tool = o.mirror == "none" ? "" : o.mirror;
  so.score_at_end = true;
  so.frames.headless = o.headless;
  so.frames.detail_pixels = o.detail_pixels;
  so.frames.mesher = o.mesher;
  so.out = o.output.out;
  so.frames.width = o.width;
  so.frames.height = o.height;
  so.end.exit_after_s = o.exit_after_s;
  so.view = "buccal";
  // Without --shot, one picture a second in: the bur at work beside the mirror.
  so.shots.shots_s = o.output.shots_s.empty() ? std::vector<double>{1.0} : o.output.shots_s;
  so.sound.sound = o.sound;
  // Headless (asked for, or no display), the sound goes to a file beside the frames.
  if (o.sound && (o.headless || !ui::whyNoDisplay().empty())) so.sound.audio_out = (fs::path(o.output.out) / "sound.wav").string();
  so.shots.frame_every_s = 20.0;
  // The score screen stays up a few seconds, then the window closes by itself (unless --stay).
  so.end.linger_s = o.stay ? -1.0 : kScoreScreenS;
  so.on_scored = [&o](const Task& task, nlohmann::ordered_json& report, const std::string& session,
                      const std::string& final_file) { recordAttemptOrWarn(o.learning, task, report, session, final_file); };
  auto run = runSimulator(so);
  if (!run && gpu::isNoDeviceError(run.error())) {
    std::printf("dentsim: %s: the demo runs on the CPU, without frames\n", run.message().c_str());
    return runCpuDemo(o);
  }
  if (!run) return fail(run.message());
  std::printf("%s on %s: %llu frames drawn, removed %.4f mm^3, ", run->windowed ? "window" : "headless",
              run->device.c_str(), static_cast<unsigned long long>(run->drawn), run->removed_mm3);
  if (run->score) std::printf("score %.2f\n", *run->score);
  else std::printf("not scored: %s\n", run->not_scored.c_str());
  // Only what the run wrote is named: a run cut short may have no score files.
  std::vector<std::string> written = run->written;
  const std::string final_path = (fs::path(o.output.out) / "final.dvol").string();
  if (std::find(written.begin(), written.end(), final_path) != written.end()) {
    auto final_tooth = loadTooth(final_path);
    if (!final_tooth) return fail(final_tooth.message());
    if (int rc = writeFinalMesh(o.output.out, *final_tooth); rc != 0) return rc;
    written.push_back((fs::path(o.output.out) / "final.ply").string());
  }
  std::printf("wrote %s:", o.output.out.c_str());
  for (const std::string& f : written) std::printf(" %s", fs::path(f).filename().c_str());
  std::printf("\n");
  if (Status st = sendPendingIfConfigured(o.learning); !st) return fail(st.message());
  return 0;
}

int runCpuDemo(const DemoOptions& o) {
  namespace fs = std::filesystem;

  auto task = builtinTask("caries");
  if (!task) return fail(task.message());
  ui::Preset preset = ui::defaultPreset();
  if (!o.params.empty()) {
    auto loaded = ui::loadPreset(o.params);
    if (!loaded) return fail(loaded.message());
    preset = std::move(*loaded);
  }
  const SimParams& params = preset.sim;

  // The tooth, saved first: the session names it, and replay starts from it.
  auto tooth = builtinMolarTooth(o.level);
  if (!tooth) return fail(tooth.message());
  const std::string initial_path = (fs::path(o.output.out) / "initial.dvol").string();
  if (Status st = saveTooth(initial_path, *tooth); !st) return fail(st.message());
  const ToothVolume initial = *tooth;
  std::printf("tooth: built-in molar, level %d, %.4f mm voxels, hash %s\n", o.level, tooth->frame.voxel_mm,
              volumeHashHex(tooth->voxels, tooth->frame).c_str());

  const std::optional<Attempt> attempt = parseAttempt(o.attempt);
  if (!attempt) return fail("--attempt: \"" + o.attempt + "\" is not one of " + attemptNames());
  auto path = cariesAttemptPath(*attempt, tooth->voxels, tooth->frame, params, task->drill_tool);
  if (!path) return fail(path.message());
  std::printf("path: the %s caries removal, %.1f s\n", o.attempt.c_str(), path->samples.empty() ? 0.0 : path->samples.back().t_s);

  SessionInfo info;
  info.created_utc = utcNow();
  info.program = std::string("dentsim ") + DENTSIM_VERSION;
  info.task = task->name;
  info.tooth_file = "initial.dvol";
  info.tooth_source = builtinToothSource(o.level);
  ScriptedSessionOptions so;
  so.drill_tool = task->drill_tool;
  so.mirror_tool = "";
  so.realtime = o.realtime;
  so.params_json = ui::presetJson(preset);
  const std::string session_path = (fs::path(o.output.out) / "session.dses").string();
  auto run = recordScriptedSession(*tooth, params, *path, session_path, info, so);
  if (!run) return fail(run.message());
  std::printf("session: %s, %llu steps in %.1f s, removed %.4f mm^3, final volume %s\n", session_path.c_str(),
              static_cast<unsigned long long>(run->steps), run->wall_s, run->removed_mm3, run->final_hash.c_str());
  if (run->steps_lost > 0) return fail(session_path + ": the recorder lost " + std::to_string(run->steps_lost) + " steps");

  const std::string final_path = (fs::path(o.output.out) / "final.dvol").string();
  if (Status st = saveTooth(final_path, *tooth); !st) return fail(st.message());
  if (int rc = writeFinalMesh(o.output.out, *tooth); rc != 0) return rc;

  auto session = readSessionFile(session_path);
  if (!session) return fail(session.message());
  auto score = scoreCut(*task, initial, *tooth, nullptr, &*session, scoreFiles(initial_path, final_path, session_path));
  if (!score) return fail(score.message());
  for (const std::string& w : score->warnings) warn(w);
  const std::string report_path = (fs::path(o.output.out) / "score.json").string();
  recordAttemptOrWarn(o.learning, *task, score->report, session_path, final_path);
  if (Status st = writeScoreReport(report_path, score->report); !st) return fail(st.message());
  const std::string png_path = (fs::path(o.output.out) / "score.png").string();
  if (Status st = writeScoreImage(png_path, *task, initial, *tooth, *score, nullptr); !st) return fail(st.message());
  std::printf("%s\n", score->summary.c_str());
  std::printf("wrote %s: initial.dvol session.dses final.dvol final.ply score.json score.png\n", o.output.out.c_str());
  if (Status st = sendPendingIfConfigured(o.learning); !st) return fail(st.message());
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* cmd = root.add_subcommand("demo", "Remove the built-in molar's caries with the scripted pen, record the session and score it");
  addOutputOptions(*cmd, &o->output,
                   {"the session, the teeth, the final mesh, the score, sound, screenshots (one at 1 s unless --shot) "
                    "and frames",
                    "dentsim-demo"});
  cmd->add_option("--level", o->level, "Octree level of the molar")->check(CLI::Range(6, 11))->capture_default_str();
  cmd->add_flag("--headless", o->headless, "No window: frames go offscreen to PNG (also when no display answers)");
  cmd->add_flag("--realtime", o->realtime, "Without a Vulkan device: run the haptic loop at its rate on its real-time thread");
  cmd->add_option("--mirror", o->mirror, "The mirror held beside the tooth, or 'none'")->capture_default_str();
  cmd->add_option("--exit-after", o->exit_after_s,
                  "Windowed: close at this loop time, at most 24 h [s] (default: a few seconds after the score)")
      ->check(finiteIn(0.0, 24.0 * 3600.0, "s"));
  cmd->add_flag("--stay", o->stay, "Windowed: keep the window open after the score until you close it");
  cmd->add_option("--width", o->width, "Window or frame width [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  cmd->add_option("--height", o->height, "Window or frame height [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  cmd->add_option("--params", o->params, "Parameter preset (.json); default: dentsim's defaults");
  cmd->add_flag("!--no-sound", o->sound, "No sound (headless: no sound.wav)");
  addDrawingOptions(*cmd, &o->detail_pixels, &o->mesher);
  cmd->add_option("--attempt", o->attempt, "The careful removal, or one with a fault: " + attemptNames())
      ->check(CLI::IsMember(attemptNameList()))
      ->capture_default_str();
  addLearningOptions(cmd, o->learning);
  cmd->callback([o, cmd, &action] {
    const Status usable = checkDemoOptions(*o, *cmd);
    action = [o, usable] { return usable ? runDemo(*o) : fail(usable.message()); };
  });
}

}  // namespace dentsim::app
