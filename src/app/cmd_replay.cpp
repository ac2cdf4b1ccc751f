// `dentsim replay SESSION [--headless] [--speed X] [--tooth X.dvol] [--out DIR] [--shot T] [--audio-out S.wav]`: replays a recorded session step for step, in a window where a display answers, checks it ends where the recording did, and can write its sound.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/replay_viewer.h"
#include "app/shared_options.h"
#include "eval/beside_file.h"
#include "eval/task_kinds.h"
#include "eval/task_tooth.h"
#include "eval/cut_score.h"
#include "audio/sound_engine.h"
#include "audio/sound_feed.h"
#include "render/camera.h"
#include "sim/scripted_paths.h"
#include "sim/tool_library.h"
#include "io/session_file.h"
#include "sim/session_run.h"
#include "ui/replay_panel.h"
#include "ui/window.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct ReplayCliOptions {
  std::string session;     // the .dses file
  std::string tooth;       // the starting volume; default: the session's own tooth file
  OutputOptions output;    // --out DIR (final.dvol, screenshots), --overwrite, --shot (the window's)
  std::string final_file;  // the deprecated -o/--output: the final volume's own path (.dvol)
  std::string report;      // score report to write (.json), when the session names a task
  std::string png;         // score picture to write (.png), when the session names a task
  std::string task;        // score against this task instead of the session's
  bool headless = false;   // no window, even where a display answers
  bool allow_other_tooth = false;
  bool json = false;       // one JSON object on stdout
  std::string audio_out;   // the session's sound, rendered offline to this WAV file (headless only)
  // The window's.
  double speed = 1.0;      // loop time per wall-clock second: one of ui::kReplaySpeeds
  bool exit_at_end = false;
  std::vector<double> seek_at;         // FROM_S TO_S: one scripted seek
  std::vector<std::string> shot_at;    // the deprecated --shot-at SECONDS FILE.png: one screenshot
  int width = 1280, height = 800;
  std::string device;
};

// Where the final volume goes: final.dvol in --out, as run and demo name it, else the deprecated
// -o FILE; empty: nowhere.
std::string finalFile(const ReplayCliOptions& o) {
  if (!o.output.out.empty()) return (std::filesystem::path(o.output.out) / "final.dvol").string();
  return o.final_file;
}

// The sound of the replay: the engine follows the loop 100 times a second of loop time, heard from
// where the simulator's first (buccal) view stands.
Result<std::unique_ptr<audio::SoundEngine>> replaySound(const std::string& audio_out, const ToothVolume& tooth,
                                                        ReplayOptions* ro, audio::SoundFeed* feed) {
  audio::EngineOptions eo;
  eo.audio_out = audio_out;
  auto engine = audio::SoundEngine::create(eo);
  if (!engine) return engine.error();
  const TissueBox box = tissueBox(tooth.voxels, tooth.frame);
  render::OrbitCamera camera;
  camera.setView(render::ViewPreset::Buccal, render::toGlm(box.centre()), float(0.5 * norm(box.hi - box.lo)));
  camera.orbit(0.0f, 0.52f);
  const render::CameraBasis basis = camera.basis();
  (*engine)->setListener(render::fromGlm(camera.eye()), render::fromGlm(basis.forward), render::fromGlm(basis.up));
  audio::SoundEngine* e = engine->get();
  ro->observe_every = 10;
  ro->observe = [e, feed](const HapticState& state) {
    e->update(feed->next(state, state.tools[size_t(PenRole::Drill)].tool.apply(kBurGripLocal)));
  };
  return engine;
}

// The task the replay is scored against: --task as the user gave it, else the session's own, a
// built-in name or a task file beside the session (a header never makes dentsim open a file
// elsewhere, and a refused file is never read, so nothing of it is echoed).
Result<Task> replayTask(const ReplayCliOptions& o, const SessionRecording& session) {
  if (!o.task.empty()) return builtinTask(o.task);
  const std::string& name = session.info.task;
  if (isBuiltinTaskName(name)) return builtinTask(name);
  auto beside = resolveBeside(o.session, name, "task");
  if (!beside) return beside.error();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(*beside, ec))
    return makeError(o.session, "task \"" + name + "\" is neither a built-in task nor a task file beside the session");
  return builtinTask(*beside);
}

// Why a finished session replays to other voxels than it recorded: every record's checksum holds,
// so its steps are the ones written; either they were written by another build (whose cut may
// differ) or the file was rewritten after the recording, checksums and all.
std::string mismatchReason(const SessionRecording& session) {
  const std::string here = std::string("dentsim ") + DENTSIM_VERSION;
  if (!session.info.program.empty() && session.info.program != here)
    return "it was recorded by " + session.info.program + " and this is " + here +
           ", whose cut may differ; replay it with that version";
  return "its records' checksums hold, so the file was changed after it was recorded (its steps rewritten) or it "
         "does not belong with this tooth; the recording and this file do not match";
}

// The replay's end, the same headless and in the window: warnings, the final volume, the score's
// files, what is printed, and the exit code.
int finishReplay(const ReplayCliOptions& o, const SessionRecording& session, const ToothVolume& initial,
                 ToothVolume& tooth, const ReplayOutcome& outcome) {
  for (const std::string& w : outcome.warnings)
    if (w != session.truncation_warning) warn(o.session + ": " + w);
  const std::string final_file = finalFile(o);
  if (!final_file.empty())
    if (Status st = saveTooth(final_file, tooth); !st) return fail(st.message());

  nlohmann::json j;
  j["session"] = o.session;
  j["steps"] = outcome.steps;
  j["final_hash"] = outcome.final_hash;
  j["recorded_final_hash"] = session.end ? session.end->final_hash : "";
  j["matches_recording"] = outcome.recorded_hash_matches;
  j["removed_mm3"] = outcome.removed_mm3;
  j["force_mismatches"] = outcome.force_mismatches;
  // What happened to the pens' devices while it was recorded: which pen failed, when and why.
  nlohmann::json device_events = nlohmann::json::array();
  for (const SessionDeviceEvent& e : session.devices)
    device_events.push_back({{"step", e.step},
                             {"t_s", double(e.step) / session.info.rate_hz},
                             {"pen", std::string(penRoleName(PenRole(e.pen)))},
                             {"state", e.state},
                             {"reason", e.reason}});
  j["device_events"] = device_events;
  std::optional<SessionScore> score;
  std::optional<Task> task;
  if (!o.task.empty() || !session.info.task.empty()) {
    // The replay stands without a score: a task this build does not know only costs the score.
    auto found = replayTask(o, session);
    if (found) task = std::move(*found);
    else warn(o.session + ": not scored: " + found.message());
  }
  if (task) {
    auto s = scoreCut(*task, initial, tooth, nullptr, &session, scoreFiles("", final_file, o.session));
    if (!s) return fail(o.session + ": " + s.message());
    score = std::move(*s);
    for (const std::string& w : score->warnings) warn(w);
    j["task"] = task->name;
    j["total"] = score->total;
    if (!o.report.empty())
      if (Status st = writeScoreReport(o.report, score->report); !st) return fail(st.message());
    if (!o.png.empty())
      if (Status st = writeScoreImage(o.png, *task, initial, tooth, *score, nullptr); !st)
        return fail(st.message());
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("replayed %llu steps of %s; final volume %s", static_cast<unsigned long long>(outcome.steps),
                o.session.c_str(), outcome.final_hash.c_str());
    if (session.end)
      std::printf(outcome.recorded_hash_matches ? " (the recording's)\n" : " (the recording ended on %s)\n",
                  session.end->final_hash.c_str());
    else
      std::printf("\n");
    std::printf("removed %.4f mm^3\n", outcome.removed_mm3);
    for (const SessionDeviceEvent& e : session.devices)
      std::printf("at %.3f s the %s pen's device was %s%s%s\n", double(e.step) / session.info.rate_hz,
                  std::string(penRoleName(PenRole(e.pen))).c_str(), e.state.c_str(), e.reason.empty() ? "" : ": ",
                  e.reason.c_str());
    if (score) std::printf("%s\n", score->summary.c_str());
  }
  std::fflush(stdout);
  // A finished session that replays to other voxels is a broken promise, not a warning.
  if (session.end && !outcome.recorded_hash_matches && !o.allow_other_tooth && session.gaps.empty())
    return fail(o.session + ": the replay ended on " + outcome.final_hash + ", the recording on " +
                session.end->final_hash + ": " + mismatchReason(session));
  return 0;
}

// The force over which a contact step counts as an error: the task's, else the default task's.
double forceThreshold(const ReplayCliOptions& o, const SessionRecording& session) {
  if (!o.task.empty() || !session.info.task.empty())
    if (auto task = replayTask(o, session)) return task->force_error_n;
  // A task this build does not know costs the score, not the timeline's marks.
  auto fallback = builtinTask(taskKindRow(TaskKind::Caries).builtin_task);
  return fallback ? fallback->force_error_n : Task{}.force_error_n;
}

int runReplayWindow(const ReplayCliOptions& o, const SessionRecording& session, ToothVolume& tooth) {
  const ToothVolume initial = tooth;
  ReplayViewerOptions vo;
  vo.title = std::filesystem::path(o.session).filename().string();
  vo.width = o.width;
  vo.height = o.height;
  vo.device = o.device;
  vo.speed = o.speed;
  vo.force_threshold_n = forceThreshold(o, session);
  vo.allow_other_tooth = o.allow_other_tooth;
  vo.exit_at_end = o.exit_at_end;
  vo.out = o.output.out;
  vo.shots_s = o.output.shots_s;
  if (o.seek_at.size() == 2) vo.seek_at = ReplayViewerOptions::Seek{o.seek_at[0], o.seek_at[1]};
  if (o.shot_at.size() == 2) {
    try {
      vo.shot_at_s = std::stod(o.shot_at[0]);
    } catch (const std::exception&) {
      return fail("--shot-at: \"" + o.shot_at[0] + "\" is not a number of seconds");
    }
    if (!std::isfinite(vo.shot_at_s) || vo.shot_at_s < 0.0 || vo.shot_at_s > kMaxLoopTimeS)
      return fail("--shot-at: \"" + o.shot_at[0] + "\" is not a time in [0, " + formatNumber(kMaxLoopTimeS) + "] s");
    vo.shot_png = o.shot_at[1];
  }
  vo.at_end = [&](const ReplayOutcome& outcome, ToothVolume& final_tooth) {
    return finishReplay(o, session, initial, final_tooth, outcome);
  };
  const bool outputs_pending = !finalFile(o).empty() || !o.report.empty() || !o.png.empty();
  auto rc = runReplayViewer(session, tooth, vo, outputs_pending);
  if (!rc) return fail(o.session + ": " + rc.message());
  return *rc;
}

// The session file a path names: a folder's session.dses. A recording that never finished left only
// its ".part" file; the message offers it rather than saying only "no such file".
Result<std::string> sessionPath(const std::string& given) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string path = fs::is_directory(given, ec) ? (fs::path(given) / "session.dses").string() : given;
  if (!fs::exists(path, ec) && fs::exists(path + ".part", ec))
    return makeError(path, "does not exist, but " + shownPath(path) + ".part does: a recording that did not finish; replay it with "
                           "`dentsim replay " + path + ".part`");
  return path;
}

// The files the replay reads (the session, its tooth, a task file) are never among those it writes.
Status checkReplayFiles(const ReplayCliOptions& o, const SessionRecording& session) {
  std::string tooth = o.tooth;
  if (tooth.empty() && !session.info.tooth_file.empty())
    if (auto beside = resolveBeside(o.session, session.info.tooth_file, "tooth.file")) tooth = *beside;
  std::vector<std::string> outputs = {finalFile(o), o.report, o.png, o.audio_out, o.shot_at.size() == 2 ? o.shot_at[1] : ""};
  // The window's screenshots in --out, named as run names them (ShotSchedule: shot-1 ... shot-N).
  for (size_t i = 1; !o.output.out.empty() && i <= o.output.shots_s.size(); ++i)
    for (const char* ext : {".png", ".json"})
      outputs.push_back((std::filesystem::path(o.output.out) / ("shot-" + std::to_string(i) + ext)).string());
  return checkOutputsAreNotInputs({o.session, tooth, o.task}, outputs);
}

// The --out folder, as run and demo keep theirs: one that holds a recording (a final.dvol among
// them) is replaced only with --overwrite.
Status prepareOutFolder(const ReplayCliOptions& o) {
  if (o.output.out.empty()) return Ok{};
  if (Status st = checkRecordingFolder(o.output.out, o.output.overwrite); !st) return st;
  std::error_code ec;
  std::filesystem::create_directories(o.output.out, ec);
  if (ec) return makeError(o.output.out, "cannot create the output folder: " + ec.message());
  return Ok{};
}

int runReplay(ReplayCliOptions o) {
  auto path = sessionPath(o.session);
  if (!path) return fail(path.message());
  o.session = *path;
  if (!ui::replaySpeedIndex(o.speed)) {
    char speed[32];
    std::snprintf(speed, sizeof speed, "%g", o.speed);
    return fail(std::string("--speed: ") + speed + " is not one of 0.25, 0.5, 1, 2, 4, 8");
  }
  auto session = readSessionFile(o.session);
  if (!session) return fail(session.message());
  if (Status st = checkReplayFiles(o, *session); !st) return fail(st.message());
  for (const std::string& w : {session->truncation_warning})
    if (!w.empty()) warn(w);
  auto tooth = resolveSessionTooth(*session, o.session, o.tooth);
  if (!tooth) return fail(tooth.message());
  // The folder is made only for a replay that will run: a refused one leaves nothing behind.
  if (Status st = prepareOutFolder(o); !st) return fail(st.message());
  // A window where a display answers; the sound is rendered offline, step for step, so it stays headless.
  if (!o.headless && o.audio_out.empty()) {
    if (std::string why = ui::whyNoDisplay(); why.empty()) return runReplayWindow(o, *session, *tooth);
    else std::fprintf(stderr, "dentsim: %s: replaying headless\n", why.c_str());
  }
  const ToothVolume initial = *tooth;
  ReplayOptions ro;
  ro.allow_other_tooth = o.allow_other_tooth;
  audio::SoundFeed feed;
  std::unique_ptr<audio::SoundEngine> sound;
  if (!o.audio_out.empty()) {
    auto engine = replaySound(o.audio_out, *tooth, &ro, &feed);
    if (!engine) return fail(engine.message());
    sound = std::move(*engine);
  }
  auto outcome = replaySession(*session, *tooth, ro);
  if (!outcome) return fail(o.session + ": " + outcome.message());
  if (sound) {
    if (Status st = sound->finish(); !st) return fail(st.message());
    if (!o.json) std::printf("wrote %s (%.1f s of sound)\n", o.audio_out.c_str(), double(sound->framesRendered()) / double(audio::EngineOptions{}.sample_rate));
  }
  return finishReplay(o, *session, initial, *tooth, *outcome);
}

}  // namespace

void addReplayCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<ReplayCliOptions>();
  CLI::App* cmd = root.add_subcommand("replay", "Replay a recorded session step for step, in a window where a display answers, and write the final volume");
  cmd->add_option("session", o->session,
                  "Session file (.dses), or a folder holding session.dses; a recording that did not finish is "
                  "session.dses.part")
      ->required();
  cmd->add_flag("--headless", o->headless, "No window: replay back to back and print the result (the default where no display answers)");
  cmd->add_option("--tooth", o->tooth, "Starting volume (.dvol); default: the tooth the session names");
  cmd->add_flag("--allow-other-tooth", o->allow_other_tooth, "Replay on a tooth whose hash differs from the session's");
  addOutputOptions(*cmd, &o->output, {"the final volume (final.dvol) and the window's screenshots (--shot)", ""});
  // The old spellings, kept working; each says once what replaced it.
  cmd->add_option_function<std::string>(
         "-o,--output",
         [o](const std::string& file) {
           warnDeprecated("replay", "-o/--output FILE", "--out DIR (writes DIR/final.dvol)");
           o->final_file = file;
         },
         "Deprecated: write the final volume to this file (.dvol); use --out DIR")
      ->group("Deprecated");
  cmd->add_option("--report", o->report, "Write the score report (.json) when the session names a task");
  cmd->add_option("--png", o->png, "Write the score picture (.png) when the session names a task");
  cmd->add_option("--task", o->task, "Score against this task (" + kindTaskNames() + " or a task file) instead of the session's");
  cmd->add_option("--audio-out", o->audio_out, "Write the session's sound to this WAV file (rendered offline, without a window)");
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->add_option("--speed", o->speed, "The window's playback speed: 0.25, 0.5, 1, 2, 4 or 8")->capture_default_str();
  cmd->add_flag("--exit-at-end", o->exit_at_end, "Close the window once the last step has played and the files are written");
  cmd->add_option("--seek-at", o->seek_at, "FROM TO: when the window's playhead first reaches FROM seconds, seek to TO seconds")
      ->expected(2)
      ->check(finiteIn(0.0, kMaxLoopTimeS, "s"));
  cmd->add_option_function<std::vector<std::string>>(
         "--shot-at",
         [o](const std::vector<std::string>& at) {
           warnDeprecated("replay", "--shot-at SECONDS FILE", "--shot SECONDS (--out DIR)");
           o->shot_at = at;
         },
         "Deprecated: SECONDS FILE.png, a screenshot of the window when the playhead reaches SECONDS; use --shot")
      ->expected(2)
      ->group("Deprecated");
  cmd->add_option("--width", o->width, "Window width [px]")->check(CLI::Range(320, 8192))->capture_default_str();
  cmd->add_option("--height", o->height, "Window height [px]")->check(CLI::Range(240, 8192))->capture_default_str();
  cmd->add_option("--device", o->device, "Vulkan device for the window (index or name part); default: the best");
  cmd->callback([o, cmd, &action] {
    // The window's own options, refused where no window opens.
    Status usable = checkOutputOptions(o->output, *cmd);
    if (usable)
      usable = refuseOption(cmd->count("--out") > 0 && cmd->count("--output") > 0, "--output",
                            "names the final volume's file, --out its folder; give --out alone");
    const bool windowless = o->headless || !o->audio_out.empty();
    for (const char* window_only : {"--speed", "--exit-at-end", "--seek-at", "--shot", "--shot-at", "--width", "--height", "--device"})
      if (usable)
        usable = refuseOption(windowless && cmd->count(window_only) > 0, window_only,
                              std::string("applies to the replay's window; ") +
                                  (o->headless ? "--headless" : "--audio-out (rendered offline)") + " opens none");
    action = [o, usable] { return usable ? runReplay(*o) : fail(usable.message()); };
  });
}

}  // namespace dentsim::app
