// The tooth a task or a recorded session starts from: a built-in tooth (the molar, alone or between its neighbours) at a level, or a volume file.
#pragma once

#include <string>

#include "core/result.h"
#include "eval/task.h"
#include "io/session_file.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A task's "tooth" that names the built-in molar (any other value but the next is a volume file).
inline constexpr const char* kBuiltinMolarTooth = "builtin:molar";
// A task's "tooth" that names the built-in molar between its neighbours, the second premolar and
// the second molar (sim/builtin_tooth.h builtinMolarNeighboursTooth): a class II beside a contact.
inline constexpr const char* kBuiltinMolarNeighboursTooth = "builtin:molar_neighbours";
// Whether a task's "tooth" names a built-in tooth, which is built at a level rather than read.
// Inline, as the two names: the app's tooth choice (a header) asks it without linking eval.
inline bool isBuiltinTooth(const std::string& tooth) {
  return tooth == kBuiltinMolarTooth || tooth == kBuiltinMolarNeighboursTooth;
}
// The built-in tooth `tooth` (kBuiltinMolarTooth or kBuiltinMolarNeighboursTooth) at `level`.
// Errors: another name, a level out of range, missing assets.
Result<ToothVolume> builtinTooth(const std::string& tooth, int level);
// A task's tooth among the embedded assets ("asset:tasks/tooth_2_caries.dvol"): what an embedded
// task's relative tooth file becomes, so the shipped course needs no files beside the program.
inline constexpr const char* kAssetToothPrefix = "asset:";

// How a session names a built-in tooth at a level, so that replay can rebuild it: "builtin:molar:LEVEL",
// "builtin:molar_neighbours:LEVEL".
inline std::string builtinToothSource(const std::string& tooth, int level) { return tooth + ":" + std::to_string(level); }
inline std::string builtinToothSource(int level) { return builtinToothSource(kBuiltinMolarTooth, level); }
// The level in a session's tooth source that names the built-in tooth `tooth` ("builtin:molar:7" ->
// 7; "builtin:molar_neighbours:7" -> 7 only for that tooth), or 0.
int builtinToothLevel(const std::string& tooth_source, const std::string& tooth = kBuiltinMolarTooth);

// A volume file, an embedded course tooth ("asset:tasks/ct_tooth_3.dvol"), or a built-in tooth by
// its session source ("builtin:molar_neighbours:9").
Result<ToothVolume> loadToothFileOrAsset(const std::string& name);
// The task's tooth: a built-in tooth at `level` (0: the task's level), an embedded course tooth,
// or the task's volume file (whose grid is its own: `level` does not apply to either).
Result<ToothVolume> taskTooth(const Task& task, int level);

// The tooth a session starts from: `override_path` when given, else the session's tooth file beside
// the session, else a built-in tooth rebuilt from the session's source. The hash is checked later,
// by the replay.
Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path);

}  // namespace dentsim
