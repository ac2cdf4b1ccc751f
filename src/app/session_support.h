// What `dentsim demo`, `replay` and `score` share: tasks by name, a session's starting tooth, the ideal cavity, the score and its files.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/task.h"
#include "io/png_file.h"
#include "io/session_file.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// The current time as ISO 8601 UTC ("2026-11-22T10:21:44Z").
std::string utcNow();
// How a session names a built-in tooth, so that replay can rebuild it: "builtin:molar:LEVEL".
std::string builtinToothSource(int level);

// A task: "caries" or "cavity" (the built-in tasks, also by their full names), or a task file.
Result<Task> builtinTask(const std::string& name_or_file);

// The tooth a session starts from: `override_path` when given, else the session's tooth file
// beside the session, else a built-in tooth rebuilt from the session's source. The hash is checked
// later, by the replay.
Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path);

// The professional's final tooth for a cavity task: its built-in path drilled on `initial`, its
// volume file, or its session replayed on `initial`.
Result<ToothVolume> idealForTask(const Task& task, const ToothVolume& initial);

struct SessionScore {
  double total = 0.0;
  std::string summary;                 // one line for the terminal
  nlohmann::ordered_json report;       // the "dentsim-score" report
  std::optional<ToothVolume> ideal;    // the ideal a cavity task made for this score (none when given)
};

struct ScoreFiles {
  std::string initial, final_, ideal, session;  // names for the report
};

// Scores `final_` against `initial` (and the ideal, for a cavity task; computed when null) with the
// session's statistics (none: an empty session).
Result<SessionScore> scoreCut(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                              const ToothVolume* ideal, const SessionRecording* session, const ScoreFiles& files);
// Writes the report as JSON (2-space indent), atomically.
Status writeScoreReport(const std::string& path, const nlohmann::ordered_json& report);
// The score picture: an occlusal and an oblique view, over-cut red, under-cut blue (no ideal: the
// cut tooth alone).
RgbImage scorePicture(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal);
// Writes the score picture.
Status writeScoreImage(const std::string& path, const ToothVolume& initial, const ToothVolume& final_,
                       const ToothVolume* ideal);

}  // namespace dentsim::app
