// Tasks by name, a session's starting tooth, the ideal cavity, and scoring with its report and picture, for the session commands.
#include "app/session_support.h"

#include <cstdio>
#include <ctime>
#include <filesystem>

#include "eval/score_image.h"
#include "eval/scores.h"
#include "eval/session_stats.h"
#include "eval/tooth_diff.h"
#include "io/atomic_file.h"
#include "model/builtin_assets.h"
#include "sim/builtin_tooth.h"
#include "sim/scripted_paths.h"
#include "sim/session_run.h"
#include "volume/tooth_file.h"

namespace dentsim::app {

namespace {
constexpr const char* kBuiltinMolar = "builtin:molar:";
}  // namespace

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string builtinToothSource(int level) { return kBuiltinMolar + std::to_string(level); }

Result<Task> builtinTask(const std::string& name) {
  std::string file;
  if (name == "caries" || name == "caries_removal") file = "tasks/caries_removal.json";
  if (name == "cavity" || name == "class1_cavity") file = "tasks/class1_cavity.json";
  if (file.empty()) {
    if (!std::filesystem::exists(name))
      return makeError(name, "no such task: the built-in ones are caries and cavity, or give a task file");
    auto task = loadTask(name);
    if (!task) return task;
    // An ideal file is named relative to the task file.
    std::string& ideal = task->cavity.ideal.path;
    if (task->cavity.ideal.kind != IdealKind::BuiltinPath && !ideal.empty() && std::filesystem::path(ideal).is_relative())
      ideal = (std::filesystem::path(name).parent_path() / ideal).string();
    return task;
  }
  const std::span<const uint8_t> bytes = builtinAssetBytes(file);
  if (bytes.empty()) return makeError(file, "not among the embedded assets");
  return parseTask(std::string(bytes.begin(), bytes.end()), "assets/" + file);
}

Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path) {
  namespace fs = std::filesystem;
  if (!override_path.empty()) return loadTooth(override_path);
  const SessionInfo& info = session.info;
  if (!info.tooth_file.empty()) {
    const fs::path beside = fs::path(session_path).parent_path() / info.tooth_file;
    if (fs::exists(beside)) return loadTooth(beside.string());
  }
  if (info.tooth_source.rfind(kBuiltinMolar, 0) == 0) {
    const std::string level = info.tooth_source.substr(std::string(kBuiltinMolar).size());
    if (level.size() <= 2 && !level.empty() && level.find_first_not_of("0123456789") == std::string::npos)
      return builtinMolarTooth(std::stoi(level));
  }
  return makeError(session_path, "cannot find the session's tooth (file \"" + info.tooth_file + "\", source \"" +
                                     info.tooth_source + "\"): give it with --tooth");
}

Result<ToothVolume> idealForTask(const Task& task, const ToothVolume& initial) {
  const IdealSpec& ideal = task.cavity.ideal;
  const std::string where = "task " + task.name + ": ideal";
  switch (ideal.kind) {
    case IdealKind::Volume:
      return loadTooth(ideal.path);
    case IdealKind::Session: {
      auto session = readSessionFile(ideal.path);
      if (!session) return session.error();
      ToothVolume tooth = initial;
      auto replayed = replaySession(*session, tooth, ReplayOptions{});
      if (!replayed) return makeError(where, replayed.message());
      return tooth;
    }
    case IdealKind::BuiltinPath: {
      if (ideal.path != "class1_cavity") return makeError(where, "no built-in path \"" + ideal.path + "\" (there is class1_cavity)");
      const SimParams params = defaultSimParams();
      auto path = cavityPreparationPath(initial.voxels, initial.frame);
      if (!path) return makeError(where, path.message());
      ToothVolume tooth = initial;
      ScriptedSessionOptions so;
      so.drill_tool = "round_bur_010";  // the bur the class I path is laid out for (CavityPathSettings)
      auto run = recordScriptedSession(tooth, params, path->path, "", SessionInfo{}, so);
      if (!run) return makeError(where, run.message());
      return tooth;
    }
  }
  return makeError(where, "unknown kind");
}

Result<SessionScore> scoreCut(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                              const ToothVolume* ideal, const SessionRecording* session, const ScoreFiles& files) {
  SessionScore out;
  if (task.kind == TaskKind::Cavity && ideal == nullptr) {
    auto i = idealForTask(task, initial);
    if (!i) return i.error();
    out.ideal = std::move(*i);
    ideal = &*out.ideal;
  }
  DiffNames names;
  if (!files.initial.empty()) names.initial = files.initial;
  if (!files.final_.empty()) names.final_ = files.final_;
  if (!files.ideal.empty()) names.ideal = files.ideal;
  auto diff = compareTeeth(initial, final_, task.kind == TaskKind::Cavity ? ideal : nullptr, task.cavity.leeway_mm, names);
  if (!diff) return diff.error();
  const SessionStats stats = session ? sessionStats(*session, task) : SessionStats{};
  const ScoreInputs inputs{task.name, files.initial, files.final_, files.ideal, files.session};
  char line[512];
  if (task.kind == TaskKind::Caries) {
    const CariesScore s = scoreCariesRemoval(*diff, stats, task);
    out.total = s.total;
    out.report = scoreReportJson(task, inputs, *diff, stats, s);
    std::snprintf(line, sizeof line,
                  "caries removal score %.2f / 100 (removal %.2f / 50, time %.2f / 25, force %.2f / 25): %.1f%% of "
                  "%.3f mm^3 caries removed; healthy enamel %.3f, dentin %.3f, pulp %.3f mm^3 removed; pulp %s",
                  s.total, s.removal, s.time, s.force, 100.0 * s.removed_fraction, s.caries_initial_mm3,
                  s.enamel_removed_mm3, s.dentin_removed_mm3, s.pulp_removed_mm3, s.pulp_exposed ? "exposed" : "not exposed");
  } else {
    auto s = scoreCavityPreparation(*diff, stats, task);
    if (!s) return s.error();
    out.total = s->total;
    out.report = scoreReportJson(task, inputs, *diff, stats, *s);
    std::snprintf(line, sizeof line,
                  "cavity preparation score %.2f / 100 (under-cut %.2f, over-cut %.2f, parallel %.2f, time %.2f, each "
                  "/ 25): ideal %.3f mm^3, under-cut %.3f mm^3, over-cut %.3f mm^3 (%.3f near, %.3f gross)",
                  s->total, s->undercut, s->overcut, s->parallel, s->time, s->ideal_mm3, s->undercut_mm3, s->overcut_mm3,
                  s->overcut_near_mm3, s->overcut_gross_mm3);
  }
  out.summary = line;
  return out;
}

Status writeScoreReport(const std::string& path, const nlohmann::ordered_json& report) {
  const std::string text = report.dump(2) + "\n";
  return writeFileAtomic(path, text);
}

RgbImage scorePicture(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal) {
  ScoreImageOptions options;
  options.oblique = true;
  return renderScoreImage(initial, final_, ideal, options).image;
}

Status writeScoreImage(const std::string& path, const ToothVolume& initial, const ToothVolume& final_,
                       const ToothVolume* ideal) {
  return writePng(path, scorePicture(initial, final_, ideal));
}

}  // namespace dentsim::app
