// Task files written: a new task's JSON, an ideal's object, and the write that reads its text back first.
#include "eval/task_writer.h"

#include <utility>

#include "eval/task_kinds.h"
#include "eval/task_tooth.h"
#include "io/atomic_file.h"

namespace dentsim {

namespace {

const char* idealKindName(IdealKind kind) {
  switch (kind) {
    case IdealKind::BuiltinPath: return "builtin_path";
    case IdealKind::Volume: return "volume";
    case IdealKind::Session: return "session";
  }
  return "volume";
}

}  // namespace

nlohmann::ordered_json idealJson(const IdealSpec& ideal) {
  nlohmann::ordered_json j = {{"kind", idealKindName(ideal.kind)}, {"path", ideal.path}};
  for (auto [key, value] : {std::pair{"final", &ideal.final_path}, {"initial_hash", &ideal.initial_hash},
                            {"final_hash", &ideal.final_hash}, {"session_hash", &ideal.session_hash}})
    if (!value->empty()) j[key] = *value;
  return j;
}

nlohmann::ordered_json crownJson(const CrownTask& c) {
  const auto band = [](double lo, double hi) { return nlohmann::ordered_json::array({lo, hi}); };
  nlohmann::ordered_json j;
  j["finish"] = c.finish;
  j["material"] = c.material;
  j["occlusal_mm"] = band(c.occlusal_lo_mm, c.occlusal_hi_mm);
  j["axial_mm"] = band(c.axial_lo_mm, c.axial_hi_mm);
  j["margin_width_mm"] = band(c.margin_lo_mm, c.margin_hi_mm);
  j["toc_deg"] = band(c.toc_lo_deg, c.toc_hi_deg);
  j["toc_near_deg"] = band(c.toc_near_lo_deg, c.toc_near_hi_deg);
  j["min_height_mm"] = c.min_height_mm;
  j["min_height_width_ratio"] = c.min_height_width_ratio;
  j["margin_above_cej_mm"] = band(c.margin_above_cej_lo_mm, c.margin_above_cej_hi_mm);
  j["undercut_tolerance_mm2"] = c.undercut_tolerance_mm2;
  j["undercut_cap"] = c.undercut_cap;
  return j;
}

nlohmann::ordered_json newTaskJson(const Task& task) {
  const TaskKindRow& kind = taskKindRow(task.kind);
  nlohmann::ordered_json j;
  j["format"] = "dentsim-task";
  j["version"] = 2;
  j["name"] = task.name;
  j["kind"] = kind.name;
  if (task.cavity_class != 0) j["cavity_class"] = cavityClassName(task.cavity_class);
  j["title"] = task.title;
  j["instructions"] = task.instructions;
  j["tooth"] = task.tooth;
  if (task.tooth == kBuiltinMolarTooth) j["level"] = task.level;
  j["tools"] = {{"drill", task.drill_tool}};
  if (!task.mirror_tool.empty()) j["tools"]["mirror"] = task.mirror_tool;
  j["target_s"] = task.target_s;
  if (hasFailureTime(kind)) j["failure_s"] = task.failure_s;
  j["force_error_n"] = task.force_error_n;
  if (task.pass_mark) j["pass_mark"] = *task.pass_mark;
  j["insertion_axis"] = {task.insertion_axis.x, task.insertion_axis.y, task.insertion_axis.z};
  j["leeway_mm"] = task.leeway_mm;
  if (task.ideal) j["ideal"] = idealJson(*task.ideal);
  if (task.from_ideal.any()) {
    nlohmann::ordered_json from_ideal = nlohmann::ordered_json::array();
    if (task.from_ideal.insertion_axis) from_ideal.push_back("insertion_axis");
    if (task.from_ideal.target_s) from_ideal.push_back("target_s");
    j["from_ideal"] = from_ideal;
  }
  if (task.view)
    j["view"] = {{"camera", task.view->camera}, {"elevation_deg", task.view->elevation_deg}, {"fixed", task.view->fixed}};
  if (task.kind == TaskKind::Crown) j[kind.coefficients] = crownJson(task.crown);
  return j;
}

Result<Task> writeTaskFile(const std::string& path, const nlohmann::ordered_json& root) {
  const std::string text = root.dump(2) + "\n";
  auto task = parseTask(text, path);
  if (!task) return task.error();
  if (Status st = writeFileAtomic(path, text); !st) return st.error();
  return task;
}

}  // namespace dentsim
