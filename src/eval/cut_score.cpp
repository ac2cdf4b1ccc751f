// Scoring a cut end to end: built-in tasks, the ideal a task names, scoreCut, and the report and picture files.
#include "eval/cut_score.h"

#include "eval/beside_file.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "eval/beside_file.h"
#include "eval/score_image.h"
#include "eval/scores.h"
#include "eval/session_stats.h"
#include "eval/task_ideal.h"
#include "eval/task_kinds.h"
#include "eval/task_tooth.h"
#include "io/atomic_file.h"
#include "model/builtin_assets.h"
#include "sim/course_paths.h"
#include "sim/session_run.h"
#include "volume/crown_estimate.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {

namespace {
constexpr std::string_view kTaskFolder = "tasks/", kTaskSuffix = ".json";

// The lead's decision, kept beside the figure so that a report says it too.
constexpr const char* kSurfaceNotScored =
    "reported, not scored: it measures the same voxels as the under-cut and over-cut parts, so scoring it too "
    "would count one fault twice; it shows where on the walls the preparation leaves the ideal";

nlohmann::ordered_json surfaceAgreementReport(const SurfaceAgreement& a) {
  nlohmann::ordered_json j = surfaceAgreementJson(a);
  j["scored"] = false;
  j["why_not_scored"] = kSurfaceNotScored;
  return j;
}

// "; surface within ±0.20 mm: 83.1%", or how it could not be measured.
std::string surfaceAgreementClause(const SurfaceAgreement& a) {
  char text[96];
  if (a.samples == 0)
    std::snprintf(text, sizeof text, "; surface within ±%.2f mm: no ideal surface at half fill", a.band_mm);
  else
    std::snprintf(text, sizeof text, "; surface within ±%.2f mm: %.1f%%", a.band_mm, a.within_percent);
  return text;
}
}  // namespace

std::vector<std::string> builtinTaskNames() {
  std::vector<std::string> names;
  for (const std::string& path : builtinAssetPaths())
    if (path.starts_with(kTaskFolder) && path.ends_with(kTaskSuffix))
      names.push_back(path.substr(kTaskFolder.size(), path.size() - kTaskFolder.size() - kTaskSuffix.size()));
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

// The built-in task a kind's name stands for, or nullptr.
const char* kindTask(const std::string& name) {
  const TaskKindRow* row = findTaskKind(name);
  return row ? row->builtin_task : nullptr;
}

}  // namespace

bool isBuiltinTaskName(const std::string& name) {
  const std::vector<std::string> names = builtinTaskNames();
  return kindTask(name) || std::find(names.begin(), names.end(), name) != names.end();
}

std::string kindTaskNames() {
  std::string list;
  for (const TaskKindRow& row : kTaskKindTable)
    if (row.builtin_task) list += (list.empty() ? "" : ", ") + std::string(row.name);
  return list;
}

Result<Task> builtinTask(const std::string& name) {
  std::string file;
  const std::vector<std::string> names = builtinTaskNames();
  if (std::find(names.begin(), names.end(), name) != names.end()) file = std::string(kTaskFolder) + name + std::string(kTaskSuffix);
  if (const char* task = kindTask(name)) file = std::string(kTaskFolder) + task + std::string(kTaskSuffix);
  if (file.empty()) {
    if (!std::filesystem::exists(name)) {
      std::string list = kindTaskNames();
      for (const std::string& n : names) list += ", " + n;
      return makeError(name, "no such task: the built-in ones are " + list + ", or give a task file");
    }
    auto task = loadTask(name);
    if (!task) return task;
    // The tooth and an ideal's files lie beside the task file (in its folder or below): a task from
    // another school cannot make dentsim open a file elsewhere.
    if (!isBuiltinTooth(task->tooth) && task->tooth.rfind(kAssetToothPrefix, 0) != 0) {
      auto tooth = resolveBeside(name, task->tooth, "tooth");
      if (!tooth) return tooth.error();
      task->tooth = *tooth;
    }
    if (task->ideal && task->ideal->kind != IdealKind::BuiltinPath) {
      auto ideal = resolveBeside(name, task->ideal->path, "ideal.path");
      if (!ideal) return ideal.error();
      task->ideal->path = *ideal;
    }
    if (task->ideal && !task->ideal->final_path.empty()) {
      auto final_path = resolveBeside(name, task->ideal->final_path, "ideal.final");
      if (!final_path) return final_path.error();
      task->ideal->final_path = *final_path;
    }
    return task;
  }
  const std::span<const uint8_t> bytes = builtinAssetBytes(file);
  if (bytes.empty()) return makeError(file, "not among the embedded assets");
  auto task = parseTask(std::string(bytes.begin(), bytes.end()), "assets/" + file);
  // An embedded task's own tooth file is embedded beside it.
  if (task && !isBuiltinTooth(task->tooth) && task->tooth.rfind(kAssetToothPrefix, 0) != 0 &&
      std::filesystem::path(task->tooth).is_relative())
    task->tooth = std::string(kAssetToothPrefix) + "tasks/" + task->tooth;
  return task;
}

Exercise exerciseOf(const Task& task) {
  Exercise e;
  e.kind = taskKindName(task.kind);
  if (task.ideal && task.ideal->kind == IdealKind::BuiltinPath) e.path = task.ideal->path;
  e.bur = task.drill_tool;
  e.insertion_axis = task.insertion_axis;
  return e;
}

Result<ToothVolume> idealForTask(const Task& task, const ToothVolume& initial, std::vector<std::string>* warnings) {
  const std::string where = "task " + task.name + ": ideal";
  if (!task.ideal) return makeError(where, "the task names no ideal");
  const IdealSpec& ideal = *task.ideal;
  if (Status st = checkIdealIdentity(ideal, initial, where); !st) return st.error();
  // A final tooth read from a file must be the one recorded, when a hash was recorded.
  const auto recorded = [&](ToothVolume tooth, const std::string& file) -> Result<ToothVolume> {
    const std::string hash = volumeHashHex(tooth.voxels, tooth.frame);
    if (!ideal.final_hash.empty() && hash != ideal.final_hash)
      return makeError(file, "the professional's final tooth changed since it was recorded as the ideal (hash " + hash +
                                 ", recorded " + ideal.final_hash + ")");
    return tooth;
  };
  switch (ideal.kind) {
    case IdealKind::Volume: {
      auto tooth = loadTooth(ideal.path);
      if (!tooth) return tooth.error();
      return recorded(std::move(*tooth), ideal.path);
    }
    case IdealKind::Session: {
      // The saved final tooth stands for the replay when it is the one recorded: scoring stays fast.
      if (!ideal.final_path.empty() && std::filesystem::exists(ideal.final_path)) {
        auto tooth = loadTooth(ideal.final_path);
        if (!tooth) return tooth.error();
        return recorded(std::move(*tooth), ideal.final_path);
      }
      auto session = readSessionFile(ideal.path);
      if (!session) return session.error();
      ToothVolume tooth = initial;
      auto replayed = replaySession(*session, tooth, ReplayOptions{});
      if (!replayed) return makeError(where, replayed.message());
      return recorded(std::move(tooth), ideal.path);
    }
    case IdealKind::BuiltinPath: {
      if (!isBuiltinPath(ideal.path))
        return makeError(where, "no built-in path \"" + ideal.path + "\" (there are " + builtinPathNames() + ")");
      // The paths find the fossa, the CEJ and the pulp with +z as the crown's axis: on a tooth whose
      // crown faces elsewhere they drill the side or the roots.
      const CrownEstimate crown = estimateCrown(initial.voxels);
      if (crown.from_enamel && crown.axis.z < std::cos(45.0 * std::numbers::pi / 180.0)) {
        char axis[96];
        std::snprintf(axis, sizeof axis, "(%.2f, %.2f, %.2f)", crown.axis.x, crown.axis.y, crown.axis.z);
        warnings->push_back(where + ": the built-in path " + ideal.path + " is laid out for a crown facing +z, but this tooth's crown faces " + axis +
                            " (estimated from the enamel): the ideal is not the cavity it names on it");
      }
      // The professional drills with the task's own bur, as the student will.
      const SimParams params = defaultSimParams();
      auto path = expertPath(exerciseOf(task), initial.voxels, initial.frame, params);
      if (!path) return makeError(where, path.message());
      ToothVolume tooth = initial;
      ScriptedSessionOptions so;
      so.drill_tool = task.drill_tool;
      auto run = recordScriptedSession(tooth, params, *path, "", SessionInfo{}, so);
      if (!run) return makeError(where, run.message());
      return tooth;
    }
  }
  return makeError(where, "unknown kind");
}

namespace {

// Reports (not scores) how the ideal cavity's surface agrees with the student's: a cavity's, an
// access's and a crown's with an ideal.
Status addSurfaceAgreement(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                           const ToothVolume& ideal, SessionScore& out) {
  auto agreement = measureSurfaceAgreement(initial, final_, ideal, task.insertion_axis);
  if (!agreement) return agreement.error();
  out.report["surface_agreement"] = surfaceAgreementReport(*agreement);
  out.summary += surfaceAgreementClause(*agreement);
  out.agreement = std::move(*agreement);
  return Ok{};
}

// What every kind's score gives the caller alike: the total, the report, the summary, the lines.
template <class KindScore>
void takeScore(SessionScore& out, const KindScore& s, const Task& task, const ScoreInputs& inputs, const ToothDiff& diff,
               const SessionStats* stats) {
  out.total = s.total;
  out.total_max = s.total_max;
  out.report = scoreReportJson(task, inputs, diff, stats, s);
  out.summary = scoreSummary(s, inputs);
  out.lines = scoreLines(s);
  out.pulp_exposed = s.pulp_exposed;
}

}  // namespace

Result<SessionScore> scoreCut(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                              const ToothVolume* ideal, const SessionRecording* session, const ScoreFiles& files) {
  SessionScore out;
  ScoreInputs inputs;
  inputs.task = task.name;
  inputs.initial = files.initial;
  inputs.final_ = files.final_;
  inputs.session = files.session;
  inputs.no_session_reason = files.no_session_reason;
  if (ideal) {
    inputs.ideal = files.ideal_spec ? *files.ideal_spec
                                    : idealVolumeFile(files.ideal.empty() ? "(given by the caller)" : files.ideal);
    inputs.ideal_from = files.ideal_from.empty() ? "command line" : files.ideal_from;
  } else if (task.ideal) {
    auto made = idealForTask(task, initial, &out.warnings);
    if (!made) return made.error();
    out.ideal = std::move(*made);
    ideal = &*out.ideal;
    inputs.ideal = task.ideal;
    inputs.ideal_from = "task";
  }
  DiffNames names;
  if (!files.initial.empty()) names.initial = files.initial;
  if (!files.final_.empty()) names.final_ = files.final_;
  if (!files.ideal.empty()) names.ideal = files.ideal;
  auto diff = compareTeeth(initial, final_, ideal, ZoneOptions{task.leeway_mm, task.insertion_axis}, names);
  if (!diff) return diff.error();
  // An ideal that removed nothing cannot be what either kind of task asks for.
  if (ideal && diff->total().target == 0)
    return makeError(names.ideal, "the ideal cavity is empty: the ideal tooth removed nothing from the initial one");
  for (std::string& w : scoreWarnings(task, *diff, names.initial)) out.warnings.push_back(std::move(w));
  inputs.warnings = out.warnings;
  std::optional<SessionStats> stats;
  if (session) stats = sessionStats(*session, task);
  const SessionStats* st = stats ? &*stats : nullptr;
  if (task.kind == TaskKind::Caries) {
    const CariesScore s = scoreCariesRemoval(*diff, st, task);
    takeScore(out, s, task, inputs, *diff, st);
    out.caries_remaining_mm3 = s.caries_remaining_mm3;
  } else if (task.kind == TaskKind::Crown) {
    auto s = scoreCrownPreparation(task, initial, final_, *diff);
    if (!s) return s.error();
    takeScore(out, *s, task, inputs, *diff, st);
    out.crown = std::move(*s);
    // An ideal is optional for a crown; with one, its surface agreement is reported as a cavity's.
    if (ideal)
      if (Status agreed = addSurfaceAgreement(task, initial, final_, *ideal, out); !agreed) return agreed.error();
  } else {
    auto s = scoreCavityPreparation(*diff, st, task);
    if (!s) return makeError(names.ideal, s.message());
    takeScore(out, *s, task, inputs, *diff, st);
    if (ideal)
      if (Status agreed = addSurfaceAgreement(task, initial, final_, *ideal, out); !agreed) return agreed.error();
  }
  // A guided attempt is not the student's alone: the report and the line say so.
  if (session && !session->info.guide_json.empty()) {
    auto guide = parseGuideJson(session->info.guide_json, files.session.empty() ? "session" : files.session);
    if (!guide) return guide.error();
    out.guided = true;
    out.report["guided"] = {{"source", guide->source},
                            {"source_hash", guide->source_hash},
                            {"stiffness_n_per_mm", guide->settings.stiffness_n_per_mm},
                            {"max_force_n", guide->settings.max_force_n}};
    char k[32];
    std::snprintf(k, sizeof k, "%.2f", guide->settings.stiffness_n_per_mm);
    out.summary += "; guided by " + guide->source + " at " + k + " N/mm";
  }
  // Read back from the report rather than filled beside it, so that the two cannot disagree.
  auto reported = ScoreReportSummary::fromJson(out.report);
  if (!reported) return Error{"the score report: " + reported.message()};
  out.reported = std::move(*reported);
  out.diff = std::move(*diff);
  return out;
}

Status writeScoreReport(const std::string& path, const nlohmann::ordered_json& report) {
  const std::string text = report.dump(2) + "\n";
  return writeFileAtomic(path, text);
}

CutMarks scorePictureRed(TaskKind kind, const ToothDiff& diff) {
  // A crown is graded on its shape, not against an ideal's volume: its over-reduction is painted.
  CutMarks red = kind == TaskKind::Crown ? CutMarks{} : kind != TaskKind::Caries ? diff.beyond_target : diff.healthy_outside_zone;
  red.merge(diff.adjacent_removed);
  return red;
}

RgbImage scorePicture(const Task& task, const ToothVolume& initial, const ToothVolume& final_, const SessionScore& score,
                      const ToothVolume* given_ideal) {
  ScoreImageOptions options;
  options.oblique = true;
  const ToothVolume* ideal = given_ideal ? given_ideal : (score.ideal ? &*score.ideal : nullptr);
  const CutMarks red = scorePictureRed(task.kind, score.diff);
  if (task.kind == TaskKind::Crown && score.crown) {
    const CutMarks paint = crownPaint(*score.crown, &final_.voxels);
    return renderScoreImage(initial, final_, nullptr, &red, options, &paint).image;
  }
  return renderScoreImage(initial, final_, ideal, &red, options).image;
}

Status writeScoreImage(const std::string& path, const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                       const SessionScore& score, const ToothVolume* given_ideal) {
  return writePng(path, scorePicture(task, initial, final_, score, given_ideal));
}

RgbImage deviationPicture(const Task& task, const ToothVolume& initial, const SessionScore& score,
                          const ToothVolume* given_ideal) {
  assert(score.agreement);
  const ToothVolume* ideal = given_ideal ? given_ideal : (score.ideal ? &*score.ideal : nullptr);
  assert(ideal);
  // The ideal tooth, its walls painted, close around the cavity; looking down the insertion axis
  // shows the floor, the oblique view the far walls.
  ScoreImageOptions options;
  options.oblique = true;
  options.fit_paint = true;
  options.view_dir = -normalized(task.insertion_axis);
  return renderScoreImage(initial, *ideal, nullptr, nullptr, options, &score.agreement->marks).image;
}

Status writeDeviationImage(const std::string& path, const Task& task, const ToothVolume& initial,
                           const SessionScore& score, const ToothVolume* given_ideal) {
  return writePng(path, deviationPicture(task, initial, score, given_ideal));
}

}  // namespace dentsim
