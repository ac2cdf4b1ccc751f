// Running sessions: the scripted recording (on the loop's thread or back to back) and the step-for-step replay.
#include "sim/session_run.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "io/pen_playback.h"
#include "sim/haptic_loop.h"
#include "sim/replay_cursor.h"
#include "sim/session_recorder.h"
#include "sim/tool_library.h"
#include "volume/volume_hash.h"

namespace dentsim {

namespace {

struct Tools {
  ToolModel drill;
  std::optional<ToolModel> mirror;
};

Result<Tools> loadTools(const std::string& drill, const std::string& mirror, const SimParams& params) {
  Tools tools;
  auto d = loadToolModel(drill, params.point_shell);
  if (!d) return d.error();
  tools.drill = std::move(*d);
  if (!mirror.empty()) {
    auto m = loadToolModel(mirror, params.point_shell);
    if (!m) return m.error();
    tools.mirror = std::move(*m);
  }
  return tools;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

SessionInfo sessionHeader(SessionInfo info, const ToothVolume& tooth, const SimParams& params,
                          const std::string& drill_tool, const std::string& mirror_tool) {
  info.rate_hz = params.device.rate_hz;
  info.drill_tool = drill_tool;
  info.mirror_tool = mirror_tool;
  info.tooth_hash = volumeHashHex(tooth.voxels, tooth.frame);
  info.tooth_level = tooth.voxels.level();
  info.voxel_mm = tooth.frame.voxel_mm;
  info.params_json = simParamsJson(params);
  return info;
}

Result<SessionOutcome> recordScriptedSession(ToothVolume& tooth, const SimParams& params, const PenPath& path,
                                             const std::string& session_path, SessionInfo info,
                                             const ScriptedSessionOptions& options) {
  if (path.samples.empty()) return makeError("scripted session", "the pen path has no samples");
  auto tools = loadTools(options.drill_tool, options.mirror_tool, params);
  if (!tools) return tools.error();
  info = sessionHeader(std::move(info), tooth, params, options.drill_tool, options.mirror_tool);
  if (!options.params_json.empty()) info.params_json = options.params_json;

  const auto t0 = std::chrono::steady_clock::now();
  HapticLoop loop(tooth.voxels, tooth.frame, params, tools->drill, tools->mirror ? &*tools->mirror : nullptr, nullptr);
  ScriptedPen drill(path, PenRole::Drill), mirror(path, PenRole::Mirror);
  std::optional<YieldingHand> drill_hand, mirror_hand;
  if (options.hand) {
    drill_hand.emplace(drill, *options.hand);
    mirror_hand.emplace(mirror, *options.hand);
  }
  loop.attach(PenRole::Drill, drill_hand ? static_cast<PenSource*>(&*drill_hand) : &drill);
  if (tools->mirror) loop.attach(PenRole::Mirror, mirror_hand ? static_cast<PenSource*>(&*mirror_hand) : &mirror);
  std::optional<GuideSpring> guide;
  if (options.guide) {
    info.guide_json = guideJson(*options.guide);
    guide.emplace(*options.guide);
    loop.setGuide(&*guide);
  }
  // The session's convention: each proxy starts on its pen's first reading.
  for (PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    PenReading first;
    ScriptedPen probe(path, role);
    if (probe.read(0.0, &first)) loop.placeTool(role, first.grip);
  }
  SessionRecorder recorder;
  const bool recording = !session_path.empty();
  if (recording)
    if (Status st = recorder.start(loop, session_path, info); !st) return st.error();

  double end_s = 0.0;
  for (const PenSample& s : path.samples) end_s = std::max(end_s, s.t_s);
  const auto steps = uint64_t(std::ceil((end_s + options.extra_s) * params.device.rate_hz - 1e-9)) + 1;
  SessionOutcome out;
  if (options.realtime) {
    if (Status st = loop.start(); !st) return st.error();
    while (loop.latest().step < steps) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    loop.stop();
    out.missed_deadlines = loop.counters().missed_deadlines.load();
  } else {
    for (uint64_t k = 0; k < steps; ++k) {
      loop.step();
      // Back to back, the loop outruns the disk; let the recorder keep up, so a kill loses at most
      // half a second of loop time.
      if (recording) recorder.keepUp();
    }
  }
  out.steps = loop.stepsRun();
  out.removed_mm3 = loop.latest().removed_mm3;
  out.final_hash = volumeHashHex(tooth.voxels, tooth.frame);
  if (recording)
    if (Status st = recorder.finish(SessionEnd{out.steps, out.final_hash, "completed"}); !st) return st.error();
  out.steps_lost = recorder.stepsLost();
  out.wall_s = secondsSince(t0);
  return out;
}

Result<ReplayOutcome> replaySession(const SessionRecording& session, ToothVolume& tooth, const ReplayOptions& options) {
  ReplayCursorOptions co;
  co.allow_other_tooth = options.allow_other_tooth;
  auto cursor = ReplayCursor::open(session, tooth, co);
  if (!cursor) return cursor.error();
  ReplayCursor& c = **cursor;
  const size_t steps = c.size();
  const uint64_t every = std::max<uint64_t>(options.observe_every, 1);
  while (!c.atEnd()) {
    c.step();
    const size_t done = c.position();
    if (options.progress && done % 1000 == 0) options.progress(done, steps);
    if (options.observe && (done % every == 0 || done == steps)) options.observe(c.loop().latest());
  }
  return c.outcome();
}

}  // namespace dentsim
