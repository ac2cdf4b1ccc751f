// What `dentsim demo`, `replay` and `run` share: the time stamp, a built-in tooth's name, a session's starting tooth.
#pragma once

#include <string>

#include "core/result.h"
#include "io/session_file.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// The current time as ISO 8601 UTC ("2026-11-22T10:21:44Z").
std::string utcNow();
// How a session names a built-in tooth, so that replay can rebuild it: "builtin:molar:LEVEL".
std::string builtinToothSource(int level);

// The tooth a session starts from: `override_path` when given, else the session's tooth file
// beside the session, else a built-in tooth rebuilt from the session's source. The hash is checked
// later, by the replay.
Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path);

}  // namespace dentsim::app
