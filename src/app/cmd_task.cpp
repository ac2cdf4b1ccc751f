// `dentsim task new|check|set-ideal`: a teacher's exercise on any tooth, written, checked and given its professional's ideal without editing JSON by hand.
//
//   1. options      `task new`'s flags, the table's lists for help and errors, files copied beside the task,
//                   what set-ideal reports
//   2. task new     the kind's defaults (eval/task_kinds.h), the tooth's own axis, the keys left to the professional
//   3. task check   every problem of a task file (eval/task_checks.h), each on its own line
//   4. set-ideal    the professional's session as the ideal, and what it set from it
//   5. the command line
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "eval/beside_file.h"
#include "eval/crown_targets.h"
#include "eval/cut_score.h"
#include "eval/task_axis.h"
#include "eval/task_checks.h"
#include "eval/task_ideal.h"
#include "eval/task_kinds.h"
#include "eval/task_tooth.h"
#include "eval/task_writer.h"
#include "model/tool_generator.h"
#include "sim/builtin_tooth.h"
#include "volume/tissue_table.h"
#include "volume/tooth_file.h"
#include "volume/tooth_frame.h"
#include "volume/tooth_layer_synth.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;

// ---- 1. options -------------------------------------------------------------------------------------------

struct TaskNewOptions {
  std::string tooth;              // a .dvol, or builtin:molar
  std::string kind = "caries";    // a kind of eval/task_kinds.h
  std::string cavity_class;       // Black's class of a cavity: I, II or V; empty: not said
  std::string finish, material;   // a crown's finish line and material (eval/crown_targets.h); empty: the tables' first
  std::string output;             // the task file
  std::string name, title, instructions;
  std::string bur, mirror = kDefaultMirror;
  int level = 0;                  // the built-in molar's level; 0: 9
  double target_s = 0, failure_s = 0, force_error_n = 3.0, leeway_mm = 0.2;
  double pass_mark = 70.0;        // the total that passes [points of 100]; negative: none (attempts only "completed")
  std::vector<double> insertion_axis;  // empty: the tooth's crown axis (a class V's: its buccal axis)
  std::string ideal_path, ideal_volume, ideal_session, ideal_final;
  std::string view;               // a view preset; empty: the simulator's default
  double view_elevation_deg = 30.0;
  bool fixed_view = false;
  bool force = false;             // replace an existing task file
};

// The kinds that end at a failure time, for --failure-s: "a caries task".
std::string kindsWithFailureTime() {
  std::string out;
  for (const TaskKindRow& row : kTaskKindTable)
    if (hasFailureTime(row)) out += (out.empty() ? "" : " or ") + kindWithArticle(row);
  return out;
}

// The Black classes that have a built-in path, joined like taskKindNameList: "I, II or V".
std::string cavityClassList(const char* separator, const char* last_separator) {
  std::string out;
  for (size_t i = 0; i < std::size(kCavityClassTable); ++i) {
    if (i > 0) out += i + 1 == std::size(kCavityClassTable) ? last_separator : separator;
    out += cavityClassName(kCavityClassTable[i].black);
  }
  return out;
}

// Each kind's default, in table order, for --help: "300, 600, 600".
template <typename Column>
std::string defaultsByKind(Column column) {
  std::string out;
  for (const TaskKindRow& row : kTaskKindTable) out += (out.empty() ? "" : ", ") + column(row);
  return out;
}

// A default for --help: 300, not 300.000000.
std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// --failure-s's help: the kinds that end at a failure time, each with its default ("Caries: ... (default 900)").
std::string failureTimeHelp() {
  std::string kinds, defaults;
  for (const TaskKindRow& row : kTaskKindTable) {
    if (!hasFailureTime(row)) continue;
    std::string name = row.name;
    name[0] = char(std::toupper(static_cast<unsigned char>(name[0])));
    kinds += (kinds.empty() ? "" : ", ") + name;
    defaults += (defaults.empty() ? "" : ", ") + numberText(row.default_failure_s);
  }
  return kinds + ": the time that earns no time points [s] (default " + defaults + ")";
}

// --bur's help: each kind's bur, and a crown's for each finish line beyond the first.
std::string burHelp() {
  std::string out = "The drill's bur (default by kind: " +
                    defaultsByKind([](const TaskKindRow& row) { return std::string(row.default_bur); });
  for (size_t i = 1; i < std::size(kCrownFinishTable); ++i)
    out += std::string("; a crown on a ") + kCrownFinishTable[i].name + ": " + kCrownFinishTable[i].default_bur;
  return out + ")";
}

// Whether the tooth is known not to be a molar: only a tooth whose layers were synthesized records
// its type (volume/tooth_layer_synth.h); any other is taken as a molar, the built-in one's kind.
bool knownNotMolar(const ToothVolume& tooth) {
  const ToothType type = ToothType(tooth.synthesized_type);
  return tooth.layers == LayerSource::Synthesized && type != ToothType::Unknown && type != ToothType::Molar;
}

// "0.8-1.5": a band as the summary prints it.
std::string bandText(double lo, double hi) { return numberText(lo) + "-" + numberText(hi); }

std::string vecText(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", v.x, v.y, v.z);
  return text;
}

// A file as the task names it, relative to the task's folder; one from elsewhere is copied there
// first, and the copy is said.
Result<std::string> nameBesideOrFail(const char* flag, const std::string& path, const std::string& task_path) {
  bool copied = false;
  auto named = nameBeside(task_path, path, &copied);
  if (!named) return makeError(flag, named.message());
  if (copied)
    std::printf("copied %s beside the task (%s): a task names only files in its own folder\n", path.c_str(),
                (fs::path(task_path).parent_path() / *named).string().c_str());
  return named;
}

// What the professional's session showed (its length, its time in contact, its bur and bur axis)
// and, for each key, whether it was set from them or kept and why.
void printWhatTheIdealSet(const std::string& task_path, const IdealRecord& r) {
  const ProfessionalFigures& p = r.professional;
  const Task& t = r.task;
  // The ideal stands: only the teacher knows whether the other bur was meant.
  if (p.drill_tool != t.drill_tool)
    warn("the professional used " + p.drill_tool + " but the task's drill is " + t.drill_tool +
         ": the ideal's walls and floor are that bur's shape, which a student with the task's bur cannot match "
         "(record the ideal with " + t.drill_tool + ", or change the task's tools.drill)");
  std::printf("%s: the professional's session lasted %.1f s, %.1f s of it with the bur in contact with the tooth\n",
              task_path.c_str(), p.elapsed_s, p.contact_s);
  if (p.bur_axis)
    std::printf("%s: the professional's mean bur axis while cutting is %s, %.1f degrees from the tooth's crown axis\n",
                task_path.c_str(), vecText(*p.bur_axis).c_str(), p.bur_axis_from_crown_deg);
  const std::string axis = vecText(t.insertion_axis);
  if (r.axis_set)
    std::printf("%s: insertion_axis set to %s, the professional's (from_ideal lists it)\n", task_path.c_str(), axis.c_str());
  else if (t.from_ideal.insertion_axis)
    std::printf("%s: insertion_axis kept %s: %s\n", task_path.c_str(), axis.c_str(), r.axis_kept_reason.c_str());
  else
    std::printf("%s: insertion_axis kept %s, the task's own (from_ideal does not list it)\n", task_path.c_str(), axis.c_str());
  if (!(p.elapsed_s > 0)) return;
  // docs/SCORING.md, section 10: the time rule, in eval/task_ideal.h.
  const Task timed = timedFromProfessional(t, p.elapsed_s);
  char rule[160];
  std::snprintf(rule, sizeof rule, "%.2f x the professional's %.1f s", kTargetFactor, p.elapsed_s);
  char rest[200];
  if (hasFailureTime(taskKindRow(t.kind)))
    std::snprintf(rest, sizeof rest, "failure_s %.1f s (%.2f x)", timed.failure_s, kFailureFactor);
  else if (std::string(taskKindRow(t.kind).coefficients) != "cavity")
    std::snprintf(rest, sizeof rest, "%s's score has no time part", kindWithArticle(taskKindRow(t.kind)).c_str());
  else
    std::snprintf(rest, sizeof rest,
                  "cavity.time_coefficient %.2f points a minute, so the time points are gone at %.1f s (%.2f x)",
                  timed.cavity.time_coefficient, kFailureFactor * p.elapsed_s, kFailureFactor);
  if (r.times_set)
    std::printf("%s: target_s set to %.1f s, %s (from_ideal lists it); %s\n", task_path.c_str(), t.target_s, rule, rest);
  else
    std::printf("%s: target_s kept %.1f s, the task's own (from_ideal does not list it); the professional's would be "
                "%.1f s, %s\n",
                task_path.c_str(), t.target_s, timed.target_s, rule);
}

// ---- 2. task new ------------------------------------------------------------------------------------------

int runTaskNew(const TaskNewOptions& o) {
  const TaskKindRow* kind = findTaskKind(o.kind);
  if (!kind) return fail("--kind: \"" + o.kind + "\" is not one of " + taskKindNameList(", ", ", "));
  if (Status st = checkOutputsAreNotInputs({o.tooth, o.ideal_volume, o.ideal_session, o.ideal_final}, {o.output}); !st)
    return fail(st.message());
  if (!o.bur.empty())
    if (Status st = checkCatalogTool("--bur", o.bur, ToolUse::Bur); !st) return fail(st.message());
  if (o.mirror != "none")
    if (Status st = checkCatalogTool("--mirror", o.mirror, ToolUse::Mirror); !st) return fail(st.message());
  const bool timed_out = hasFailureTime(*kind);
  if (o.failure_s > 0 && !timed_out) return fail("--failure-s applies to " + kindsWithFailureTime() + ", not to " + o.kind);
  // The class: given, or the one the built-in ideal path cuts; a path of another class is a mistake.
  int black = 0;
  if (!o.cavity_class.empty()) {
    if (kind->kind != TaskKind::Cavity) return fail("--class applies to a cavity task, not to " + o.kind);
    black = cavityClassFromName(o.cavity_class);
    if (!findCavityClass(black)) return fail("--class: \"" + o.cavity_class + "\" is not one of " + cavityClassList(", ", ", "));
    if (const int path_class = builtinPathClass(o.ideal_path); path_class != 0 && path_class != black)
      return fail("--class " + o.cavity_class + " does not go with --ideal-path " + o.ideal_path + ", a class " +
                  cavityClassName(path_class) + " path");
  } else if (kind->kind == TaskKind::Cavity) {
    black = builtinPathClass(o.ideal_path);
  }
  const CavityClassRow* klass = findCavityClass(black);
  // A crown's finish line and material: given, or the tables' first (chamfer, all-ceramic).
  const CrownFinishRow* finish = nullptr;
  const CrownMaterialRow* material = nullptr;
  if (kind->kind != TaskKind::Crown) {
    for (auto [flag, value] : {std::pair{"--finish", &o.finish}, {"--material", &o.material}})
      if (!value->empty()) return fail(std::string(flag) + " applies to a crown task, not to " + o.kind);
  } else {
    finish = findCrownFinish(o.finish.empty() ? kCrownFinishTable[0].name : o.finish);
    if (!finish) return fail("--finish: \"" + o.finish + "\" is not one of " + crownFinishNameList(", ", ", "));
    material = findCrownMaterial(o.material.empty() ? kCrownMaterialTable[0].name : o.material);
    if (!material) return fail("--material: \"" + o.material + "\" is not one of " + crownMaterialNameList(", ", ", "));
  }
  if (fs::exists(o.output) && !o.force) return fail(o.output + ": exists; give --force to replace it");
  const int ideals = !o.ideal_path.empty() + !o.ideal_volume.empty() + !o.ideal_session.empty();
  if (ideals > 1) return fail("give at most one of --ideal-path, --ideal-volume and --ideal-session");
  if (!o.ideal_final.empty() && o.ideal_session.empty()) return fail("--ideal-final goes with --ideal-session");
  const bool builtin = o.tooth == kBuiltinMolarTooth;
  if (o.level != 0 && !builtin) return fail("--level applies to the built-in molar; a .dvol keeps its own grid");

  // The tooth decides the defaults: its crown axis is the insertion axis, its tissues what the kind needs.
  auto tooth = builtin ? builtinMolarTooth(o.level > 0 ? o.level : 9) : loadTooth(o.tooth);
  if (!tooth) return fail(tooth.message());
  if (lacksRequiredTissue(*kind, tooth->voxels.materialTotals()))
    return fail(o.tooth + ": no " + findTissue(kind->required_tissue)->name + " in this tooth, so " +
                kindWithArticle(*kind) + " " + kind->without_tissue + " (" + kind->tissue_hint + ")");
  const ToothAxes& axes = tooth->frame.tooth;
  if (axes.crown_source == AxisSource::Assumed)
    warn(o.tooth + " has no tooth frame: the crown is taken as +z (voxelize it again to find it)");

  Task t;
  t.name = o.name.empty() ? fs::path(o.output).stem().string() : o.name;
  t.kind = kind->kind;
  t.cavity_class = black;
  const std::string tooth_name = builtin ? "the built-in molar" : fs::path(o.tooth).stem().string();
  t.title = o.title.empty() ? std::string(klass ? klass->title : kind->title) + " (" + tooth_name + ")" : o.title;
  t.instructions = o.instructions.empty() ? kind->instructions : o.instructions;
  // A task names files only in its own folder or below it (eval/beside_file.h): a tooth or ideal
  // from elsewhere is copied there, so the course folder holds all it names.
  if (builtin) {
    t.tooth = o.tooth;
    t.level = o.level > 0 ? o.level : 9;
  } else {
    auto named = nameBesideOrFail("--tooth", o.tooth, o.output);
    if (!named) return fail(named.message());
    t.tooth = *named;
  }
  // A crown's bur cuts its finish line: the finish's own, which for the first finish is the kind's.
  t.drill_tool = !o.bur.empty() ? o.bur : klass ? klass->bur : finish ? finish->default_bur : kind->default_bur;
  if (finish) {
    t.crown = crownTargets(*finish, *material);
    if (knownNotMolar(*tooth)) t.crown.min_height_mm = kCrownMinHeightOtherMm;
  }
  if (o.mirror != "none") t.mirror_tool = o.mirror;
  t.target_s = o.target_s > 0 ? o.target_s : kind->default_target_s;
  if (timed_out) t.failure_s = o.failure_s > 0 ? o.failure_s : kind->default_failure_s;
  t.force_error_n = o.force_error_n;
  if (o.pass_mark >= 0) t.pass_mark = o.pass_mark;
  // The tooth's own axis, not the grid's: the crown axis (a class V's buccal axis), as far as the
  // tooth's frame knows it.
  std::string axis_from;
  if (!o.insertion_axis.empty()) {
    if (o.insertion_axis.size() != 3) return fail("--insertion-axis: expected three numbers x,y,z");
    t.insertion_axis = Vec3{o.insertion_axis[0], o.insertion_axis[1], o.insertion_axis[2]};
    axis_from = "as given";
  } else {
    t.insertion_axis = axisForTaskFile(defaultInsertionAxis(kind->kind, black, axes));
    const bool buccal = black == 5;
    const AxisSource source = buccal ? axes.buccal_source : axes.crown_source;
    axis_from = std::string("the tooth's ") + (buccal ? "buccal axis (a class V is cut from buccal)" : "crown axis") +
                (source == AxisSource::Assumed ? ", assumed" : "");
    if (buccal && source == AxisSource::Assumed)
      std::printf("note: %s's buccal side is not known, so it is taken as the convention's; give voxelize "
                  "--buccal-axis, or --insertion-axis here\n",
                  o.tooth.c_str());
  }
  t.leeway_mm = o.leeway_mm;
  const char* builtin_ideal = klass ? klass->builtin_ideal : kind->builtin_ideal;
  if (!o.ideal_path.empty()) {
    t.ideal = idealBuiltinPath(o.ideal_path);
  } else if (!o.ideal_volume.empty()) {
    auto named = nameBesideOrFail("--ideal-volume", o.ideal_volume, o.output);
    if (!named) return fail(named.message());
    t.ideal = idealVolumeFile(*named);
  } else if (builtin_ideal) {
    t.ideal = idealBuiltinPath(builtin_ideal);
  }
  // What the teacher left to the defaults, the professional's session sets (set-ideal).
  t.from_ideal.insertion_axis = o.insertion_axis.empty();
  t.from_ideal.target_s = o.target_s <= 0 && o.failure_s <= 0;
  if (!o.view.empty()) t.view = TaskView{o.view, o.view_elevation_deg, o.fixed_view};
  if (auto written = writeTaskFile(o.output, newTaskJson(t)); !written) return fail(written.message());
  std::printf("wrote %s: %s task \"%s\" on %s, insertion axis (%.4f, %.4f, %.4f): %s\n", o.output.c_str(), o.kind.c_str(),
              t.title.c_str(), o.tooth.c_str(), t.insertion_axis.x, t.insertion_axis.y, t.insertion_axis.z, axis_from.c_str());
  if (finish) {
    const CrownTask& c = t.crown;
    std::printf("the crown's targets (%s, on a %s): occlusal reduction %s mm, axial %s mm, the %s %s mm wide, "
                "convergence %s deg (near %s), height at least %s mm%s; change them in the task's crown object\n",
                c.material.c_str(), c.finish.c_str(), bandText(c.occlusal_lo_mm, c.occlusal_hi_mm).c_str(),
                bandText(c.axial_lo_mm, c.axial_hi_mm).c_str(), c.finish.c_str(),
                bandText(c.margin_lo_mm, c.margin_hi_mm).c_str(), bandText(c.toc_lo_deg, c.toc_hi_deg).c_str(),
                bandText(c.toc_near_lo_deg, c.toc_near_hi_deg).c_str(), numberText(c.min_height_mm).c_str(),
                knownNotMolar(*tooth) ? (std::string(" (a ") + toothTypeName(ToothType(tooth->synthesized_type)) + ")").c_str()
                                      : "");
  }
  if (!o.ideal_session.empty()) {
    auto record = setTaskIdeal(o.output, o.ideal_session, o.ideal_final);
    if (!record) return fail(record.message());
    std::printf("the ideal is %s (final tooth %s)\n", record->session_file.c_str(), record->final_file.c_str());
    printWhatTheIdealSet(o.output, *record);
    return 0;
  }
  if (t.ideal && t.ideal->kind == IdealKind::BuiltinPath)
    std::printf("the ideal is the built-in path %s until you record one: dentsim task set-ideal %s --session PROF.dses\n",
                t.ideal->path.c_str(), o.output.c_str());
  if (t.from_ideal.any())
    std::printf("set-ideal will set %s from the professional's session (the task's from_ideal)\n",
                t.from_ideal.insertion_axis && t.from_ideal.target_s ? "the insertion axis and the times"
                : t.from_ideal.insertion_axis                       ? "the insertion axis"
                                                                    : "the times");
  return 0;
}

// ---- 3. task check ----------------------------------------------------------------------------------------

// Every problem of a task file, each on its own line; errors make the exit status 1.
int runTaskCheck(const std::string& path) {
  auto task = builtinTask(path);
  if (!task) return fail(task.message());
  const TaskProblems problems = checkTask(*task);
  for (const std::string& w : problems.warnings) std::printf("%s: warning: %s\n", path.c_str(), w.c_str());
  for (const std::string& e : problems.errors) std::printf("%s: error: %s\n", path.c_str(), e.c_str());
  if (!problems.ok()) return 1;
  const int black = taskCavityClass(*task);
  // What says more than the kind: a cavity's class, a crown's material and finish line.
  const std::string detail = black ? std::string(" (class ") + cavityClassName(black) + ")"
                             : task->kind == TaskKind::Crown ? " (" + task->crown.material + ", " + task->crown.finish + ")"
                                                             : "";
  std::printf("%s: ok: %s task%s \"%s\" on %s, drill %s%s\n", path.c_str(), taskKindName(task->kind), detail.c_str(),
              task->title.c_str(), task->tooth.c_str(), task->drill_tool.c_str(),
              task->ideal ? (", ideal " + task->ideal->path).c_str() : ", no ideal");
  return 0;
}

// ---- 4. set-ideal -----------------------------------------------------------------------------------------

int runTaskSetIdeal(const std::string& task, const std::string& session, const std::string& final_tooth) {
  // The task file is rewritten on purpose; the session and final tooth are read, never written.
  if (Status st = checkOutputsAreNotInputs({session, final_tooth}, {task}); !st) return fail(st.message());
  auto record = setTaskIdeal(task, session, final_tooth);
  if (!record) return fail(record.message());
  std::printf("%s: the ideal is now %s (final tooth %s; tooth %s, final %s, session %s)\n", task.c_str(),
              record->session_file.c_str(), record->final_file.c_str(), record->spec.initial_hash.c_str(),
              record->spec.final_hash.c_str(), record->spec.session_hash.c_str());
  printWhatTheIdealSet(task, *record);
  return 0;
}

}  // namespace

// ---- 5. the command line ----------------------------------------------------------------------------------

void addTaskCommand(CLI::App& root, Action& action) {
  CLI::App* cmd = root.add_subcommand("task", "Write, check and set the ideal of an exercise (a task file)");
  cmd->require_subcommand(1);

  auto n = std::make_shared<TaskNewOptions>();
  CLI::App* make = cmd->add_subcommand("new", "Write a valid task on a tooth");
  make->add_option("--tooth", n->tooth, "The tooth: a .dvol, or builtin:molar")->required();
  make->add_option("--kind", n->kind, taskKindNameList(", ", " or "))->capture_default_str();
  make->add_option("--class", n->cavity_class,
                   "A cavity's Black class: " + cavityClassList(", ", " or ") +
                       " (its built-in ideal path and bur; a class V's axis is the buccal one)");
  make->add_option("--finish", n->finish,
                   "A crown's finish line: " + crownFinishNameList(", ", " or ") + " (default " + kCrownFinishTable[0].name +
                       "); it picks the bur and the margin's width");
  make->add_option("--material", n->material,
                   "A crown's material: " + crownMaterialNameList(", ", " or ") + " (default " + kCrownMaterialTable[0].name +
                       "); it sets the reductions and the margin's width (docs/SCORING.md)");
  make->add_option("-o,--output", n->output, "The task file to write (.json)")->required();
  make->add_option("--name", n->name, "The task's name (default: the file's stem)");
  make->add_option("--title", n->title, "One line for the task picker");
  make->add_option("--instructions", n->instructions, "What the student is to do");
  make->add_option("--bur", n->bur, burHelp());
  make->add_option("--mirror", n->mirror, "The mirror, or none")->capture_default_str();
  make->add_option("--level", n->level, "The built-in molar's level (default 9)")->check(CLI::Range(DS_MIN_LEVEL, DS_MAX_LEVEL));
  make->add_option("--target-s", n->target_s,
                   "The time a good student needs [s] (default by kind: " +
                       defaultsByKind([](const TaskKindRow& row) { return numberText(row.default_target_s); }) +
                       ", until set-ideal sets it from the professional)")
      ->check(finiteIn(1.0, 1e6, "s"));
  make->add_option("--failure-s", n->failure_s, failureTimeHelp())
      ->check(finiteIn(1.0, 1e6, "s"));
  make->add_option("--force-error-n", n->force_error_n, "A contact sample above this force is an error [N]")
      ->check(finiteIn(0.01, 1000.0, "N"))
      ->capture_default_str();
  make->add_option("--leeway-mm", n->leeway_mm, "Leeway around the target [mm]")
      ->check(finiteIn(0.0, 1.0, "mm"))
      ->capture_default_str();
  make->add_option("--pass-mark", n->pass_mark, "The total that passes [points of 100]; -1: none, attempts are only completed")
      ->check(finiteIn(-1.0, 100.0, "points"))
      ->capture_default_str();
  make->add_option("--insertion-axis", n->insertion_axis,
                   "The bur's axis x,y,z (default: the tooth's crown axis, a class V's buccal axis, until set-ideal sets it "
                   "from the professional)")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e6, 1e6, ""));
  make->add_option("--ideal-path", n->ideal_path, "The ideal is this built-in path");
  make->add_option("--ideal-volume", n->ideal_volume, "The ideal is this professional's final tooth (.dvol)");
  make->add_option("--ideal-session", n->ideal_session, "The ideal is this professional's session (.dses), as set-ideal");
  make->add_option("--ideal-final", n->ideal_final, "With --ideal-session: its final tooth (.dvol), saving the replay");
  make->add_option("--view", n->view, "The first view: occlusal, buccal, lingual, mesial or distal");
  make->add_option("--view-elevation", n->view_elevation_deg, "The first view's elevation [deg]")
      ->check(finiteIn(-89.0, 89.0, "deg"))
      ->capture_default_str();
  make->add_flag("--fixed-view", n->fixed_view, "The student cannot turn the view (indirect vision: work in the mirror)");
  make->add_flag("--force", n->force, "Replace an existing task file");
  make->callback([n, &action] { action = [n] { return runTaskNew(*n); }; });

  auto check_path = std::make_shared<std::string>();
  CLI::App* check = cmd->add_subcommand("check", "Validate a task file and name each problem");
  check->add_option("task", *check_path, "The task file")->required();
  check->callback([check_path, &action] { action = [check_path] { return runTaskCheck(*check_path); }; });

  auto set = std::make_shared<std::array<std::string, 3>>();
  CLI::App* ideal = cmd->add_subcommand("set-ideal", "Make a professional's recorded session the task's ideal");
  ideal->add_option("task", (*set)[0], "The task file")->required();
  ideal->add_option("--session", (*set)[1], "The professional's session (.dses), recorded on the task's tooth")->required();
  ideal->add_option("--final", (*set)[2], "Its final tooth (.dvol; default: replay the session)");
  ideal->callback([set, &action] { action = [set] { return runTaskSetIdeal((*set)[0], (*set)[1], (*set)[2]); }; });
}

}  // namespace dentsim::app
