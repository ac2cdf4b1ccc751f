// The task-kind table: every kind of exercise dentsim scores, one row each; the task parser, `task new`, `task check` and the class report take their kinds from it.
//
// Contents
//   1. The row: name, words, `task new`'s defaults, the built-in ideal and task, the tissue it needs, the pulp rule
//   2. The table (add a kind here, then its score in eval/cut_score.cpp)
//   3. A cavity's Black classes that have a built-in path
//   4. Look-ups and lists for messages, checked at compile time
//
// Header-only, like volume/tissue_table.h, so that the CLI tests can hold `task new` and its help to
// the same rows without linking eval.
#pragma once

#include <cstddef>
#include <iterator>
#include <string>

#include "eval/task.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. the row --------------------------------------------------------------------------------------

// What an exposed pulp means for a kind (docs/SCORING.md): a fault everywhere but where the pulp
// chamber is what the student is to open.
enum class PulpRule {
  ExposureCaps,  // a fault: the task's pulp_exposure_cap caps the total, and the class report flags it
  MustOpen,      // the target: no fault, and access.unopened_cap caps a total that left it closed
};

struct TaskKindRow {
  TaskKind kind;
  const char* name;             // the task file's "kind", and the score report's and the class report's ("caries")
  const char* article;          // "a" or "an", for noun
  const char* noun;             // the kind in a sentence ("caries task", "access cavity")
  int since_version;            // the first task-file version that has the kind
  // `task new`'s defaults; a teacher's flags replace them, and set-ideal the times (task_ideal.h).
  const char* title;            // the title, before " (the tooth's name)"
  const char* instructions;     // what the student is to do
  const char* default_bur;      // the drill's bur (a bur in assets/tools/tools.json)
  double default_target_s;      // target_s [s], > 0
  double default_failure_s;     // failure_s [s], > default_target_s; 0: the kind has no failure time (the
                                // cavity's time_coefficient takes the time points away instead)
  // The ideal: required in the task file, or the kind is measured against the tooth's own lesion. A
  // new task starts with builtin_ideal as its ideal (nullptr: none); a cavity's class may name
  // another (section 3).
  bool ideal_required;
  const char* builtin_ideal;    // a built-in path (sim/course_paths.h), or nullptr
  // The built-in task (assets/tasks/<it>.json) that the kind's name also names wherever a task is
  // asked for (`score --task caries`); nullptr: the name is no task's.
  const char* builtin_task;
  const char* coefficients;     // the task-file object holding the kind's score coefficients
  // The tissue the tooth must hold for the exercise to mean anything (Material::Empty: none), what
  // the kind lacks without it, and how a tooth is given it.
  Material required_tissue;
  const char* without_tissue;   // "has nothing to remove"
  const char* tissue_hint;      // "voxelize it with --caries or a caries label"
  PulpRule pulp;
};

// ---- 2. the table ------------------------------------------------------------------------------------

// Rows are in TaskKind order: the parser, the help and the error messages list kinds in this order.
// The times are only a starting point: set-ideal sets them from the professional (task_ideal.h).
inline constexpr TaskKindRow kTaskKindTable[] = {
    {TaskKind::Caries, "caries", "a", "caries task", 1, "Remove the caries",
     "Open the lesion from the occlusal surface and remove all the carious tissue, keeping the healthy enamel and "
     "dentin around it and the pulp closed.",
     "round_bur_010", 300, 900, false, nullptr, "caries_removal", "caries", Material::Caries, "has nothing to remove",
     "voxelize it with --caries or a caries label", PulpRule::ExposureCaps},
    {TaskKind::Cavity, "cavity", "a", "cavity", 1, "Prepare the cavity",
     "Prepare the cavity as the professional did: the same outline, depth and walls parallel to the insertion axis, "
     "without touching the pulp.",
     "fissure_bur_010", 600, 0, true, "class1_cavity", "class1_cavity", "cavity", Material::Empty, "", "", PulpRule::ExposureCaps},
    // An access is scored as a cavity, with its own rule for the pulp in place of the exposure cap.
    {TaskKind::Access, "access", "an", "access cavity", 2, "Open the pulp chamber",
     "Prepare the endodontic access: go through the occlusal surface into the pulp chamber and remove its roof, "
     "keeping the walls of the crown.",
     "round_bur_014", 600, 0, true, "access_cavity", nullptr, "cavity", Material::Pulp, "has no chamber to open",
     "voxelize it with --pulp or --fill-enclosed pulp", PulpRule::MustOpen},
    // A crown is measured from the prepared shape itself (eval/crown_score.h); an ideal, when the task
    // has one, is compared surface to surface and reported.
    {TaskKind::Crown, "crown", "a", "crown preparation", 2, "Prepare the tooth for a full crown",
     "Reduce the occlusal surface and every axial wall by the crown's thickness, with walls converging 10 to 20 "
     "degrees, no undercut, and an even, continuous finish line at the gingival margin, without touching the "
     "neighbouring teeth.",
     "chamfer_bur_016", 900, 0, false, "crown_prep", "crown_preparation", "crown", Material::Empty, "", "",
     PulpRule::ExposureCaps},
};

// ---- 3. a cavity's classes ---------------------------------------------------------------------------

// A cavity's Black class where it says more than the kind: the built-in path that cuts it (and starts
// as a new task's ideal), its bur and its title. eval/task_axis.h's builtinPathClass reads it backward.
struct CavityClassRow {
  int black;                    // Black's class, 1 to 6
  const char* builtin_ideal;    // a built-in path (sim/course_paths.h)
  const char* bur;              // `task new`'s drill for the class
  const char* title;            // `task new`'s title for the class
};

inline constexpr CavityClassRow kCavityClassTable[] = {
    {1, "class1_cavity", "fissure_bur_010", "Prepare a class I cavity"},
    {2, "class2_cavity", "fissure_bur_010", "Prepare a class II cavity"},
    // A round bur cuts the rounded axial wall that follows the cervical curve (docs/SCORING.md, section 10).
    {5, "class5_cavity", "round_bur_010", "Prepare a class V cavity"},
};

// ---- 4. look-ups and lists ---------------------------------------------------------------------------

inline constexpr size_t kTaskKindCount = std::size(kTaskKindTable);

// The row of a kind.
constexpr const TaskKindRow& taskKindRow(TaskKind kind) { return kTaskKindTable[size_t(kind)]; }

// The row a task file's "kind" names, or nullptr.
inline const TaskKindRow* findTaskKind(const std::string& name) {
  for (const TaskKindRow& row : kTaskKindTable)
    if (name == row.name) return &row;
  return nullptr;
}

// The row of a Black class that has a built-in path, or nullptr.
constexpr const CavityClassRow* findCavityClass(int black) {
  for (const CavityClassRow& row : kCavityClassTable)
    if (row.black == black) return &row;
  return nullptr;
}

// Whether the kind's tasks end at a failure time (the file's failure_s), rather than losing their
// time points by the cavity's time_coefficient.
constexpr bool hasFailureTime(const TaskKindRow& row) { return row.default_failure_s > 0; }

// "a caries task", "an access cavity": the kind as a sentence's subject.
inline std::string kindWithArticle(const TaskKindRow& row) { return std::string(row.article) + " " + row.noun; }

// Every kind's name for messages and help, joined by `separator`, the last by `last_separator`:
// ", " and " or " give "caries, cavity or access".
inline std::string taskKindNameList(const char* separator, const char* last_separator) {
  std::string out;
  for (size_t i = 0; i < kTaskKindCount; ++i) {
    if (i > 0) out += i + 1 == kTaskKindCount ? last_separator : separator;
    out += kTaskKindTable[i].name;
  }
  return out;
}

namespace task_kinds_internal {

constexpr bool rowsAreInKindOrder() {
  for (size_t i = 0; i < kTaskKindCount; ++i)
    if (size_t(kTaskKindTable[i].kind) != i) return false;
  return true;
}

constexpr bool timesAreSane() {
  for (const TaskKindRow& row : kTaskKindTable)
    if (!(row.default_target_s > 0) || (row.default_failure_s != 0 && !(row.default_failure_s > row.default_target_s)))
      return false;
  return true;
}

// A kind whose file must name an ideal must have one for `task new` to write.
constexpr bool requiredIdealsHaveADefault() {
  for (const TaskKindRow& row : kTaskKindTable)
    if (row.ideal_required && row.builtin_ideal == nullptr) return false;
  return true;
}

constexpr bool classesAreBlacks() {
  for (const CavityClassRow& row : kCavityClassTable)
    if (row.black < 1 || row.black > 6) return false;
  return true;
}

}  // namespace task_kinds_internal

// taskKindRow indexes by the enum, and the parser turns a row's index back into its kind.
static_assert(task_kinds_internal::rowsAreInKindOrder(), "kTaskKindTable's rows must follow TaskKind's order");
static_assert(task_kinds_internal::timesAreSane(), "a kind's default target_s is > 0 and its failure_s 0 or beyond it");
static_assert(task_kinds_internal::requiredIdealsHaveADefault(), "a kind that needs an ideal names a built-in one");
static_assert(task_kinds_internal::classesAreBlacks(), "Black's classes are 1 to 6");

}  // namespace dentsim
