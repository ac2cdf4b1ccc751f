// Scoring a cut end to end: a task by name, the ideal it names, the comparison, the score with its warnings, the report and the picture.
//
// `dentsim score`, `replay`, `demo`, the simulator's score screen and `dentsim bench scores` all score
// through scoreCut, so a cut scores the same whichever way it arrives.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/crown_score.h"
#include "eval/score_summary.h"
#include "eval/scores.h"
#include "eval/surface_agreement.h"
#include "eval/task.h"
#include "eval/tooth_diff.h"
#include "io/png_file.h"
#include "io/session_file.h"
#include "sim/course_paths.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A task: a built-in one by its name ("caries_removal", "class2_cavity", ...; a kind's name, "caries"
// or "cavity", for the built-in task its row in eval/task_kinds.h names), or a task file.
Result<Task> builtinTask(const std::string& name_or_file);
// The names of the built-in tasks (assets/tasks/*.json, embedded), sorted.
std::vector<std::string> builtinTaskNames();
// Whether builtinTask takes `name` as a built-in task's: one of builtinTaskNames() or a kind's short name.
bool isBuiltinTaskName(const std::string& name);
// The kinds' names that stand for a built-in task, for messages and help: "caries, cavity".
std::string kindTaskNames();

// The professional's final tooth that task.ideal names (which must be set): its built-in path
// (sim/course_paths.h) drilled on `initial` with the task's bur, its volume file, or its session replayed on `initial`. What may make it wrong for
// this tooth (a built-in path laid out for a crown facing +z on a tooth whose crown faces elsewhere)
// is added to *warnings.
// What the scripted dentist (sim/course_paths.h) needs of the task: its kind, its ideal's built-in
// path (empty when it has none of that kind), its drill and its insertion axis.
Exercise exerciseOf(const Task& task);

Result<ToothVolume> idealForTask(const Task& task, const ToothVolume& initial, std::vector<std::string>* warnings);

struct SessionScore {
  double total = 0.0;
  double total_max = 100.0;            // 100, or less when parts were not scored
  std::string summary;                 // one line for the terminal
  nlohmann::ordered_json report;       // the "dentsim-score" report
  ScoreReportSummary reported;         // the report's keys that its readers use, typed (read back from `report`)
  std::optional<ToothVolume> ideal;    // the ideal this score made from the task (none when given or none)
  ToothDiff diff;                      // the comparison, for the picture
  // Cavity and access: how the ideal cavity's surface agrees with the student's (reported, not
  // scored: docs/SCORING.md, "Surface agreement"); none for a caries task.
  std::optional<SurfaceAgreement> agreement;
  std::vector<std::string> warnings;   // also in the report
  // What a screen shows (the report holds the same and more).
  std::vector<ScoreLine> lines;        // parts and deductions, in the report's order
  std::optional<double> caries_remaining_mm3;  // caries removal only
  std::optional<CrownScore> crown;     // a crown preparation: its measures and criteria (the picture paints them)
  bool pulp_exposed = false;
  bool guided = false;                 // the session's drill had a guide's spring (the report's "guided" says which)
};

struct ScoreFiles {
  std::string initial, final_, ideal, session;  // names for the report; ideal: a file given in place of the task's
  std::string no_session_reason = "no session was given";  // why there is no session, when there is none
  std::optional<IdealSpec> ideal_spec;  // what a given ideal is, when not the volume file `ideal`
  std::string ideal_from;               // where a given ideal was named; empty: "command line"
};
// The names of a score's files, the rest left at their defaults.
inline ScoreFiles scoreFiles(std::string initial, std::string final_, std::string session) {
  ScoreFiles f;
  f.initial = std::move(initial);
  f.final_ = std::move(final_);
  f.session = std::move(session);
  return f;
}

// Scores `final_` against `initial` with the session's statistics (none: the parts that need a
// session are not scored). The ideal is `ideal` when given, else the task's own (made here), else
// none: a caries task then measures against its caries and their access.
Result<SessionScore> scoreCut(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                              const ToothVolume* ideal, const SessionRecording* session, const ScoreFiles& files);
// Writes the report as JSON (2-space indent), atomically.
Status writeScoreReport(const std::string& path, const nlohmann::ordered_json& report);
// The voxels the score picture paints red: the over-cut of a cavity or access, or the healthy tissue
// cut outside the allowed zone of a caries removal; and in every kind, what was cut of an adjacent
// tooth (a crown's only red fog: its reduction map is painted on the surface, scorePicture).
CutMarks scorePictureRed(TaskKind kind, const ToothDiff& diff);
// The score picture: an occlusal and an oblique view; red is scorePictureRed, blue the under-cut of
// an ideal. A crown's shows the prepared tooth painted instead (crownPaint: the reduction map green
// within, blue under, red over; the finish line yellow; the undercut magenta), with no ideal's tint.
RgbImage scorePicture(const Task& task, const ToothVolume& initial, const ToothVolume& final_, const SessionScore& score,
                      const ToothVolume* given_ideal);
// Writes the score picture.
Status writeScoreImage(const std::string& path, const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                       const SessionScore& score, const ToothVolume* given_ideal);
// The deviation picture: the ideal tooth seen down the insertion axis and obliquely, its cavity's
// surface green within the band, red where the student cut beyond it, blue where short of it.
// score.agreement must be set (a cavity or access task) and the ideal given or made by the score.
RgbImage deviationPicture(const Task& task, const ToothVolume& initial, const SessionScore& score,
                          const ToothVolume* given_ideal);
// Writes the deviation picture.
Status writeDeviationImage(const std::string& path, const Task& task, const ToothVolume& initial,
                           const SessionScore& score, const ToothVolume* given_ideal);

}  // namespace dentsim
