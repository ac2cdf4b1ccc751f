// The tooth a task or a recorded session starts from: the built-in molar at a level, or a volume file.
#pragma once

#include <string>

#include "core/result.h"
#include "eval/task.h"
#include "io/session_file.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A task's "tooth" that names the built-in molar (any other value is a volume file).
inline constexpr const char* kBuiltinMolarTooth = "builtin:molar";
// A task's tooth among the embedded assets ("asset:tasks/tooth_2_caries.dvol"): what an embedded
// task's relative tooth file becomes, so the shipped course needs no files beside the program.
inline constexpr const char* kAssetToothPrefix = "asset:";

// How a session names the built-in molar at a level, so that replay can rebuild it: "builtin:molar:LEVEL".
std::string builtinToothSource(int level);
// The level in a session's tooth source that names the built-in molar ("builtin:molar:7" -> 7), or 0.
int builtinToothLevel(const std::string& tooth_source);

// A volume file, or an embedded course tooth ("asset:tasks/ct_tooth_3.dvol").
Result<ToothVolume> loadToothFileOrAsset(const std::string& name);
// The task's tooth: the built-in molar at `level` (0: the task's level), an embedded course tooth,
// or the task's volume file (whose grid is its own: `level` does not apply to either).
Result<ToothVolume> taskTooth(const Task& task, int level);

// The tooth a session starts from: `override_path` when given, else the session's tooth file beside
// the session, else a built-in tooth rebuilt from the session's source. The hash is checked later,
// by the replay.
Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path);

}  // namespace dentsim
