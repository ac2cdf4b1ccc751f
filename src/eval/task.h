// Task: what a scored exercise asks of the student (tooth, tools, time limits, thresholds, the ideal), read from assets/tasks/*.json.
//
// docs/SCORING.md gives every key. This file only parses the text; eval/cut_score.h finds a task by
// name among the embedded assets and makes the ideal it names, eval/task_tooth.h its tooth.
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"

namespace dentsim {

enum class TaskKind {
  Caries,  // caries removal (the paper's Table 4)
  Cavity,  // cavity preparation against a professional's result (Table 5)
  Access,  // endodontic access: scored as a cavity, but the pulp chamber must be opened
  Crown,   // a full-crown preparation, measured as examiners measure it (docs/CROWN_PREPARATION.md)
};

// Where the professional's final tooth comes from; idealForTask (eval/cut_score.h) turns it into a volume.
enum class IdealKind {
  BuiltinPath,  // a scripted bur path by name, run on the task's tooth
  Volume,       // a .dvol file of the professional's final tooth
  Session,      // a professional's .dses session, replayed on the task's tooth
};

struct IdealSpec {
  IdealKind kind = IdealKind::Volume;
  std::string path;  // name (BuiltinPath) or file; a relative file is relative to the task file's folder
  // Kind Session: the professional's final tooth saved beside the session (`task set-ideal` writes
  // it), used in place of replaying the session when its hash is final_hash. Empty: replay.
  std::string final_path;
  // The ideal's identity (volumeHashHex / the session file's hash), written by `dentsim task set-ideal`
  // and checked when the ideal is made, so that a changed tooth or ideal file is named, not scored
  // against. Empty: not recorded (hand-written tasks, built-in paths).
  std::string initial_hash;  // the tooth the professional started from
  std::string final_hash;    // the professional's final tooth
  std::string session_hash;  // XXH3 of the session file's bytes (kind Session)
};

// An ideal that is a volume file, with no identity recorded.
inline IdealSpec idealVolumeFile(std::string path) {
  IdealSpec spec;
  spec.path = std::move(path);
  return spec;
}
// An ideal that is a built-in path by name.
inline IdealSpec idealBuiltinPath(std::string name) {
  IdealSpec spec;
  spec.kind = IdealKind::BuiltinPath;
  spec.path = std::move(name);
  return spec;
}

// How the simulator first shows the tooth for this task. A fixed view cannot be turned: the
// indirect-vision exercises, where the cavity can be seen only in the mirror.
struct TaskView {
  std::string camera = "buccal";   // a view preset: occlusal, buccal, lingual, mesial, distal
  double elevation_deg = 30.0;     // the eye raised this far above the preset's direction [deg], [-89, 89]
  bool fixed = false;              // the student cannot orbit, pan or zoom
};

// The caries-removal terms beyond the paper's Table 4; defaults are docs/SCORING.md's.
struct CariesTask {
  double healthy_coefficient = 0.5;   // points per percent of the caries volume of healthy tissue cut outside the zone
};

// The cavity-preparation terms; defaults are docs/SCORING.md's.
struct CavityTask {
  double undercut_coefficient = 1.0;  // points per percent of the ideal volume left standing
  double overcut_coefficient = 1.0;   // points per percent of the ideal volume cut beyond it
  double parallel_coefficient = 0.01; // points per contact sample tilted beyond parallel_error_deg
  double time_coefficient = 5.0;      // points per minute beyond target_s
  double force_coefficient = 0.5;     // points per percent of contact samples over force_error_n (all of them: 50)
  double parallel_error_deg = 10.0;   // tolerated tilt of the bur from insertion_axis [deg], (0, 90]
  // Over-cut within leeway_mm of the ideal counts this much of its volume in the over-cut part, [0, 1]:
  // a wall within the ±0.2 mm band is the bur wavering at the margin, as the professional's own
  // second cut would (docs/SCORING.md section 5).
  double near_overcut_weight = 0.0;
};

// The access cavity's rule beyond a cavity's; the default is docs/SCORING.md's.
struct AccessTask {
  double unopened_cap = 40.0;         // a pulp chamber left closed caps the total at this [points of 100], [0, 100]
};

// The full-crown preparation's targets (docs/CROWN_PREPARATION.md gives each one's source). `task new
// --kind crown` fills them from the finish line and the crown's material (eval/crown_targets.h); the
// task file holds them, and a teacher may change any. Heights are along the insertion axis.
struct CrownTask {
  std::string finish = "chamfer";        // the finish line: "chamfer" or "shoulder"
  std::string material = "all-ceramic";  // "all-ceramic", "metal-ceramic" or "metal": what set the bands
  double occlusal_lo_mm = 1.5;           // occlusal reduction's band [mm]: less is under-reduced
  double occlusal_hi_mm = 2.0;           //   more is over-reduced
  double axial_lo_mm = 1.0;              // axial reduction's band [mm]
  double axial_hi_mm = 1.5;
  double margin_lo_mm = 0.8;             // the finish line's width [mm]
  double margin_hi_mm = 1.5;
  double toc_lo_deg = 10.0;              // total occlusal convergence recommended (Goodacre 2001) [deg]
  double toc_hi_deg = 20.0;
  double toc_near_lo_deg = 4.0;          // still acceptable down to this (4-10 as some schools teach) [deg]
  double toc_near_hi_deg = 30.0;         // and up to this (21-30 judged acceptable) [deg]
  double min_height_mm = 4.0;            // occlusocervical height: 4 on molars, 3 on other teeth [mm]
  double min_height_width_ratio = 0.4;   // height / width [-]
  double margin_above_cej_lo_mm = 0.0;   // the margin's height over the CEJ, where the tooth has one [mm]
  double margin_above_cej_hi_mm = 1.0;
  double undercut_tolerance_mm2 = 0.5;   // undercut shadow up to this is near; beyond it fails [mm^2]
  double undercut_cap = 50.0;            // an undercut beyond the tolerance caps the total here [points of 100], [0, 100]
};

// Damage to an adjacent tooth, a deduction in every kind; the defaults are docs/SCORING.md's
// ("Adjacent teeth"). Removal at or under the noise floor is the bur grazing a contact, not damage,
// and costs nothing; above it, min_points + coefficient x the volume removed.
struct AdjacentTask {
  double coefficient = 100.0;         // points per mm^3 of neighbour removed, >= 0 (1 point per 0.01 mm^3)
  double min_points = 25.0;           // what any damage above the noise floor costs at least [points], [0, 100]
  double noise_voxels = 3.0;          // the noise floor: removal up to this many voxels' fill is not damage [voxels], >= 0
};

// The keys of a task that `dentsim task new` filled in by default, so that `task set-ideal` sets
// them from the professional's session (docs/SCORING.md, section 10): the task file's "from_ideal".
struct FromIdeal {
  bool insertion_axis = false;        // the professional's mean bur axis while cutting
  bool target_s = false;              // the task's times (task_ideal.h's timedFromProfessional)
  bool any() const { return insertion_axis || target_s; }
};

struct Task {
  std::string name;                   // file stem ("caries_removal"); letters, digits, '_', '-', '.'
  TaskKind kind = TaskKind::Caries;
  std::string title;                  // one line for the UI; the name when the file has none
  std::string instructions;           // what the student is to do, a few sentences for the task picker; may be empty
  // What the simulator starts when the command line does not say otherwise (taskTooth, `run`).
  std::string tooth;                  // "builtin:molar" or a volume file (relative to the task's folder)
  int level = 9;                      // octree level of the built-in molar, DS_MIN_LEVEL..DS_MAX_LEVEL
  std::string drill_tool;             // tool on the drill pen ("round_bur_010")
  std::string mirror_tool;            // tool on the mirror pen; empty when none
  double target_s = 0.0;              // time a good student needs [s], > 0
  double failure_s = 0.0;             // caries: time that earns no time points [s], > target_s; 0 for cavity
  double force_error_n = 3.0;         // a contact sample above this force is an error [N], > 0
  // Where the student may cut (docs/SCORING.md, "The allowed zone"), for both kinds.
  Vec3 insertion_axis{0, 0, 1};       // the bur's ideal +z axis (tip along -z), unit length, tooth grid axes
  double leeway_mm = 0.2;             // shell around the target that a cut may reach unpunished [mm], [0, 1]
  std::optional<IdealSpec> ideal;     // the professional's final tooth; required for kinds Cavity and Access
  FromIdeal from_ideal;               // the keys set-ideal sets from the professional; none by default
  // Black's class of a cavity (1 to 6: I to VI); 0: not given. Kind Cavity only. It decides which
  // axes are valid (eval/task_axis.h): a class V is cut from the buccal or lingual side.
  int cavity_class = 0;
  std::optional<TaskView> view;       // the simulator's first view; none: the simulator's default
  double pulp_exposure_cap = 50.0;    // an exposed pulp caps the total at this [points of 100], [0, 100]; not for Access
  // The total that passes [points of 100], [0, 100]; none: an attempt is only completed, neither
  // passed nor failed (the learning record's verb, eval/learning_record.h).
  std::optional<double> pass_mark;
  CariesTask caries;                  // kind Caries only (defaults otherwise)
  CavityTask cavity;                  // kinds Cavity and Access (defaults otherwise)
  AccessTask access;                  // kind Access only (defaults otherwise)
  CrownTask crown;                    // kind Crown only (defaults otherwise)
  AdjacentTask adjacent;              // every kind; scored only on a tooth with a neighbour
};

// "caries", "cavity", "access" or "crown".
const char* taskKindName(TaskKind kind);
// Black's class in Roman numerals, "I" to "VI", for 1 to 6; "" for anything else.
const char* cavityClassName(int cavity_class);
// The class of "I" to "VI", or 0 for any other text.
int cavityClassFromName(const std::string& name);

// Parses a task file's text, version 2 or the older version 1 (whose insertion_axis, leeway_mm and
// ideal sit inside "cavity"). Errors are one line, "<where>: <key path>: <problem>": unknown keys,
// missing keys, wrong types, values out of range, a key that does not belong to the task's kind.
Result<Task> parseTask(const std::string& json_text, const std::string& where);
// Reads and parses a task file (at most 1 MiB). Errors name the path.
Result<Task> loadTask(const std::string& path);

}  // namespace dentsim
