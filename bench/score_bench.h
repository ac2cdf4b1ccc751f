// The score benchmark (`dentsim bench scores`): scripted expert and novice attempts at every built-in task on the molar, scored, to show that the score tells them apart.
//
// Construct validity, measured: every attempt of sim/novice_paths.h (made for each task by
// sim/course_paths.h) is drilled by the scripted pen on the same tooth, recorded, and scored
// through eval's scoreCut like any student's. The expert
// should score at least 20 points above each novice, and each novice should lose its points in the
// part that matches its fault. Scripted attempts are deterministic, so a second run gives the same
// scores to the last bit.
//
// The built-in tasks' times are a student's (minutes); the scripted expert works in seconds. So
// the bench sets each task's times from its expert, as a teacher sets them from the professional's
// recorded attempt: the target is target_factor times the expert's time, and the time points are
// gone at failure_factor times it (a caries task's failure_s; a cavity or access task's time_coefficient).
//
// Contents
//   1. Running the attempts
//   2. Which part each fault should cost, and the checks
//   3. The report: JSON, Markdown, SVG
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "eval/task.h"
#include "sim/novice_paths.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// ---- 1. running the attempts --------------------------------------------------------------------------

struct ScoreBenchSettings {
  std::vector<Attempt> attempts{kAttempts.begin(), kAttempts.end()};  // the expert is always run first
  double target_factor = 1.25;   // a task's target_s: this times its expert's elapsed time
  double failure_factor = 3.0;   // no time points left at this times the expert's elapsed time
  std::string work_dir;          // where the sessions are written and read back (removed after); required
  std::string picture_dir;       // score pictures <task>-<attempt>.png go here; empty: none
};

// One attempt's score and what it did.
struct AttemptScore {
  std::string task;                                      // the task's name ("caries_removal", "class2_cavity", ...)
  TaskKind kind = TaskKind::Caries;
  Attempt attempt = Attempt::Expert;
  double total = 0.0, total_max = 100.0, paper_total = 0.0;
  std::vector<std::pair<std::string, double>> parts;     // each scored part's points; deductions negative
  double elapsed_s = 0.0;                                // the recorded session's length [s]
  double max_force_n = 0.0;
  double mean_force_n = 0.0;                             // over the contact samples
  double force_over_percent = 0.0;                       // of the contact samples [%]
  double caries_removed_percent = 0.0;                   // of the initial caries
  double healthy_removed_mm3 = 0.0;
  double healthy_outside_mm3 = 0.0;                      // outside the allowed zone
  double undercut_percent = 0.0, overcut_percent = 0.0;  // cavity and access: of the ideal
  bool pulp_exposed = false;
  std::string final_hash;                                // volumeHash of the cut tooth
  std::vector<std::string> warnings;
  nlohmann::ordered_json report;                         // the whole "dentsim-score" report
};

struct ScoreBenchResult {
  int level = 0;
  double voxel_mm = 0.0;
  std::vector<Task> tasks;           // as scored: the tasks given, with the times set from their experts
  std::vector<AttemptScore> scores;  // each task's attempts in the tasks' order, the expert first, then settings' order
};

// Runs every attempt at each task on `molar` (the built-in molar at some level). `progress` is told
// each attempt as it starts (may be empty). Errors: a task the course has no scripted attempts at
// (sim/course_paths.h), or a failed run.
Result<ScoreBenchResult> runScoreBench(const ToothVolume& molar, const std::vector<Task>& tasks,
                                       const ScoreBenchSettings& settings,
                                       const std::function<void(const std::string&)>& progress = {});

// ---- 2. the checks ----------------------------------------------------------------------------------------

// The parts of a task that an attempt's fault should cost ("healthy", "force", ...).
std::vector<std::string> faultParts(TaskKind kind, Attempt attempt);

struct NoviceCheck {
  std::string task;
  Attempt attempt = Attempt::Expert;
  double gap = 0.0;             // expert's total - novice's total [points]
  double lost_in_fault = 0.0;   // of the points lost against the expert, those in the fault's parts
  double lost = 0.0;            // all points lost against the expert, part by part (gains not counted)
  bool gap_ok = false;          // gap >= min_gap
  bool part_ok = false;         // lost_in_fault is the larger share of the loss
};
std::vector<NoviceCheck> checkNovices(const ScoreBenchResult& result, double min_gap = 20.0);

// ---- 3. the report ------------------------------------------------------------------------------------------

nlohmann::ordered_json scoreBenchJson(const ScoreBenchResult& result);
std::string scoreBenchMarkdown(const ScoreBenchResult& result);
std::string scoreBenchSvg(const ScoreBenchResult& result);

}  // namespace dentsim::bench
