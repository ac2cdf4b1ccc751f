// Running sessions: the scripted recording (on the loop's thread or back to back) and the step-for-step replay.
#include "sim/session_run.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "io/pen_playback.h"
#include "sim/haptic_loop.h"
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
      // Back to back, the loop outruns the disk; give the recorder room when its ring fills up.
      while (recording && loop.droppedRecords() == 0 && recorder.stepsWritten() + 8192 < loop.stepsRun())
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
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
  const std::string where = "replay";
  ReplayOutcome out;
  if (!session.truncation_warning.empty()) out.warnings.push_back(session.truncation_warning);
  const std::string hash = volumeHashHex(tooth.voxels, tooth.frame);
  if (hash != session.info.tooth_hash) {
    const std::string what = "the tooth's hash " + hash + " is not the session's " + session.info.tooth_hash +
                             " (" + session.info.tooth_source + "): a session replays only on the tooth it was recorded on";
    if (!options.allow_other_tooth) return makeError(where, what);
    out.warnings.push_back(what);
  }
  if (session.steps.empty()) return makeError(where, "the session holds no steps");
  auto params = parseSimParams(session.info.params_json, "session parameters");
  if (!params) return params.error();
  std::vector<SimParams> changes;
  for (const SessionParams& p : session.params) {
    auto c = parseSimParams(p.params_json, "session parameters " + std::to_string(p.serial));
    if (!c) return c.error();
    changes.push_back(std::move(*c));
  }
  auto tools = loadTools(session.info.drill_tool, session.info.mirror_tool, *params);
  if (!tools) return tools.error();
  // A guided session's forces held the guide's spring: the same guide, from the header, makes them again.
  std::optional<GuideSpring> guide;
  if (!session.info.guide_json.empty()) {
    auto g = parseGuideJson(session.info.guide_json, where);
    if (!g) return g.error();
    guide.emplace(std::move(*g));
  }

  // Steps up to the first gap: past it the loop's state is unknown.
  size_t count = session.steps.size();
  if (!session.gaps.empty()) {
    const uint64_t gap = session.gaps.front().first_step;
    for (size_t i = 0; i < session.steps.size(); ++i)
      if (session.steps[i].step >= gap) {
        count = i;
        break;
      }
    out.warnings.push_back("the session lost steps from step " + std::to_string(gap) + "; replayed the " +
                           std::to_string(count) + " before them");
  }
  const std::span<const SessionStep> steps(session.steps.data(), count);
  if (steps.empty()) return makeError(where, "no step before the session's first gap");

  HapticLoop loop(tooth.voxels, tooth.frame, *params, tools->drill, tools->mirror ? &*tools->mirror : nullptr, nullptr);
  ReplayPen drill(steps, PenRole::Drill), mirror(steps, PenRole::Mirror);
  loop.attach(PenRole::Drill, &drill);
  if (tools->mirror) loop.attach(PenRole::Mirror, &mirror);
  if (guide) loop.setGuide(&*guide);
  for (size_t r = 0; r < 2; ++r) {
    // Each proxy starts on its pen's first reading.
    for (const SessionStep& s : steps)
      if (s.hasReading(r)) {
        loop.placeTool(PenRole(r), s.reading[r].grip);
        break;
      }
  }
  size_t next_change = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    while (next_change < session.params.size() && session.params[next_change].from_step <= steps[i].step) {
      loop.setParams(changes[next_change]);
      ++next_change;
    }
    const StepReport& report = loop.step();
    const Vec3 force = report.stepped[0] ? report.tools[0].display.force : Vec3{};
    const Vec3& recorded = steps[i].force_n[0];
    if (force.x != recorded.x || force.y != recorded.y || force.z != recorded.z) {
      if (out.force_mismatches == 0) out.first_mismatch = steps[i].step;
      ++out.force_mismatches;
    }
    if (options.progress && (i + 1) % 1000 == 0) options.progress(i + 1, steps.size());
    if (options.observe && ((i + 1) % std::max<uint64_t>(options.observe_every, 1) == 0 || i + 1 == steps.size()))
      options.observe(loop.latest());
  }
  out.steps = loop.stepsRun();
  out.removed_mm3 = loop.latest().removed_mm3;
  out.final_hash = volumeHashHex(tooth.voxels, tooth.frame);
  if (!session.end) {
    out.warnings.push_back("the session has no end record (it was not finished cleanly)");
  } else {
    out.recorded_hash_matches = session.end->final_hash == out.final_hash;
  }
  if (out.force_mismatches > 0)
    out.warnings.push_back("the replayed force differs from the recorded one at " + std::to_string(out.force_mismatches) +
                           " steps, first at step " + std::to_string(out.first_mismatch));
  return out;
}

}  // namespace dentsim
