// Running a recorded session: a scripted drilling recorded to a session file, and the replay of any session file, step for step.
//
// Both drive the same HapticLoop, so a replay feeds every step the readings the recorded step
// consumed and ends on the same voxels. The session's convention: each tool's proxy starts on its
// pen's first reading, and parameter sets come into force at the step the file names.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "io/pen_path_file.h"
#include "io/session_file.h"
#include "model/tool_generator.h"
#include "sim/guide_spring.h"
#include "sim/haptic_loop.h"
#include "sim/sim_params.h"
#include "sim/yielding_hand.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- recording a scripted session -------------------------------------------------------------------

struct ScriptedSessionOptions {
  std::string drill_tool = kDefaultBur;
  std::string mirror_tool;        // empty: no mirror
  bool realtime = false;          // run the loop on its real-time thread at the set's rate; else back to back
  double extra_s = 0.05;          // keep stepping this long after the path's last sample [s]
  std::string params_json;        // the preset text the header records, the same tactile set as `params`
                                  // with the stages above's sections (ui::presetJson); empty: simParamsJson
  std::optional<GuidePath> guide; // a guide's spring on the drill (recorded in the header); none: unguided
  std::optional<HandSettings> hand;  // the script's hand gives way to the rendered force; none: rigid
};

struct SessionOutcome {
  uint64_t steps = 0;
  std::string final_hash;         // volumeHash of the tooth afterwards
  double removed_mm3 = 0.0;
  uint64_t missed_deadlines = 0;  // real-time runs only
  uint64_t steps_lost = 0;        // steps the recorder could not keep (0 in a good run)
  double wall_s = 0.0;
};

// `info` with what the session's header takes from its start: the loop's rate, the tools, the
// tooth's hash, level and voxel size, and the parameter set (simParamsJson; a caller that owns the
// preset's other sections may replace info.params_json with the whole preset's text).
SessionInfo sessionHeader(SessionInfo info, const ToothVolume& tooth, const SimParams& params,
                          const std::string& drill_tool, const std::string& mirror_tool);

// Drills `tooth` (edited in place) with a scripted pen playing `path` and records the session to
// `session_path` (empty: records nothing). `info` is the header: rate, tools, tooth hash and parameters are filled in here.
Result<SessionOutcome> recordScriptedSession(ToothVolume& tooth, const SimParams& params, const PenPath& path,
                                             const std::string& session_path, SessionInfo info,
                                             const ScriptedSessionOptions& options);

// ---- replay -----------------------------------------------------------------------------------------

struct ReplayOptions {
  bool allow_other_tooth = false;  // replay although the tooth's hash differs (a warning, not an error)
  std::function<void(uint64_t step, uint64_t steps)> progress;  // called every 1000 steps; may be empty
  // Called with the loop's state after every observe_every steps, and after the last step: what
  // follows the replay at a frame or block rate (the sound engine). May be empty.
  std::function<void(const HapticState& state)> observe;
  uint64_t observe_every = 10;
};

struct ReplayOutcome {
  uint64_t steps = 0;              // steps replayed
  std::string final_hash;
  double removed_mm3 = 0.0;
  bool recorded_hash_matches = false;   // the session's end record names the same final hash
  uint64_t force_mismatches = 0;   // steps whose drill force differs from the recorded one
  uint64_t first_mismatch = 0;     // the first such step
  std::vector<std::string> warnings;  // truncation, gaps, other tooth, no end record
};

// Replays `session` on `tooth` (its starting volume; edited in place). Errors: a tooth whose hash
// differs from the session's (unless allowed), a parameter set or tool that does not load, a
// session without steps.
Result<ReplayOutcome> replaySession(const SessionRecording& session, ToothVolume& tooth, const ReplayOptions& options);

}  // namespace dentsim
