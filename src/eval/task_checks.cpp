// A task's checks against the tool catalog, its tooth and its ideal.
#include "eval/task_checks.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/volume_frame.h"
#include "eval/crown_targets.h"
#include "eval/cut_score.h"
#include "eval/task_axis.h"
#include "eval/task_tooth.h"
#include "model/tool_generator.h"
#include "volume/tissue_table.h"
#include "volume/volume_hash.h"

namespace dentsim {

namespace {

// The catalog's burs that cut the finish line, "chamfer_bur_016 or chamfer_bur_018"; where the
// catalog has none, the finish's own default.
std::string finishBurs(const CrownFinishRow& finish) {
  std::vector<std::string> names;
  for (const ToolSpec& tool : toolCatalog())
    if (isBur(tool.kind) && cutsCrownFinish(finish, tool.name)) names.push_back(tool.name);
  if (names.empty()) names.push_back(finish.default_bur);
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

// A crown's finish line is the print of the bur's end: a warning, not an error, since a teacher
// may mean another bur (a round-ended one for a deep chamfer), but a student given it cannot cut
// the finish the task measures.
void checkCrownBur(const Task& task, TaskProblems& out) {
  const CrownFinishRow* finish = findCrownFinish(task.crown.finish);
  if (!finish) return;  // the parser allows none other
  const CrownFinishRow* cut = crownFinishOfBur(task.drill_tool);
  if (cut == finish) return;
  const std::string wanted = "a " + task.crown.finish + " is cut with " + finishBurs(*finish);
  if (!cut)
    out.warnings.push_back("tools.drill: \"" + task.drill_tool + "\" cuts no crown finish line (" +
                           crownFinishNameList(", ", " or ") + "); " + wanted);
  else
    out.warnings.push_back("tools.drill: \"" + task.drill_tool + "\" cuts a " + cut->name + ", but crown.finish is " +
                           task.crown.finish + "; " + wanted);
}

void checkTools(const Task& task, TaskProblems& out) {
  const ToolSpec* drill = findTool(task.drill_tool);
  if (task.kind == TaskKind::Crown) checkCrownBur(task, out);
  if (!drill || !isBur(drill->kind))
    out.errors.push_back("tools.drill: \"" + task.drill_tool + "\" is not a bur in the tool catalog (assets/tools/tools.json)");
  if (task.mirror_tool.empty()) return;
  const ToolSpec* mirror = findTool(task.mirror_tool);
  if (!mirror || mirror->kind != ToolKind::Mirror)
    out.errors.push_back("tools.mirror: \"" + task.mirror_tool + "\" is not a mirror in the tool catalog");
}

// "0.067 mm^3" of neighbour the professional's tooth lacks against the task's; "" when none: an
// expert is to leave the teeth beside the preparation whole.
std::string adjacentCutText(const ToothVolume& tooth, const ToothVolume& ideal) {
  const size_t n = size_t(Material::Neighbour);
  const uint64_t before = tooth.voxels.materialTotals().fill_sum[n], after = ideal.voxels.materialTotals().fill_sum[n];
  if (after >= before) return "";
  const double v = tooth.frame.voxel_mm;
  char text[64];
  std::snprintf(text, sizeof text, "%.3f mm^3", double(before - after) / DS_FILL_FULL * v * v * v);
  return text;
}

// The tooth's tissues and axes, and the ideal made on it.
void checkOnTooth(const Task& task, const ToothVolume& tooth, TaskProblems& out) {
  const TaskKindRow& kind = taskKindRow(task.kind);
  if (lacksRequiredTissue(kind, tooth.voxels.materialTotals()))
    out.errors.push_back(std::string("tooth: no ") + findTissue(kind.required_tissue)->name + " in " + task.tooth +
                         ", so the " + kind.noun + " " + kind.without_tissue);
  const ToothAxes& axes = tooth.frame.tooth;
  if (axes.crown_source == AxisSource::Assumed)
    out.warnings.push_back("tooth: " + task.tooth + " has no tooth frame; the crown is taken as +z");
  if (auto problem = checkInsertionAxis(task, axes)) out.errors.push_back("insertion_axis: " + *problem);
  if (!task.ideal) return;
  std::vector<std::string> ideal_warnings;
  auto ideal = idealForTask(task, tooth, &ideal_warnings);
  if (!ideal) out.errors.push_back("ideal: " + ideal.message());
  else if (volumeHashHex(ideal->voxels, ideal->frame) == volumeHashHex(tooth.voxels, tooth.frame))
    out.errors.push_back("ideal: the professional's tooth is the task's tooth uncut");
  else if (std::string cut = adjacentCutText(tooth, *ideal); !cut.empty())
    out.warnings.push_back("ideal: the professional cut " + cut +
                           " of an adjacent tooth; its ideal cavity leaves that out, but the professional's own attempt loses "
                           "the adjacent-tooth deduction");
  for (std::string& w : ideal_warnings) out.warnings.push_back(std::move(w));
}

}  // namespace

bool lacksRequiredTissue(const TaskKindRow& kind, const MaterialTotals& totals) {
  return kind.required_tissue != Material::Empty && totals.voxels[size_t(kind.required_tissue)] == 0;
}

TaskProblems checkTask(const Task& task) {
  TaskProblems out;
  checkTools(task, out);
  auto tooth = taskTooth(task, 0);
  if (!tooth) out.errors.push_back("tooth: " + tooth.message());
  else checkOnTooth(task, *tooth, out);
  return out;
}

}  // namespace dentsim
