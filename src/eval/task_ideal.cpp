// setTaskIdeal and checkIdealIdentity: the professional's session copied beside the task, the task's "ideal" rewritten with its hashes.
#include "eval/task_ideal.h"

#include <cassert>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "eval/beside_file.h"
#include "eval/cut_score.h"
#include "eval/session_stats.h"
#include "eval/task_axis.h"
#include "eval/task_kinds.h"
#include "eval/task_tooth.h"
#include "eval/task_writer.h"
#include "io/atomic_file.h"
#include "io/file_hash.h"
#include "io/session_file.h"
#include "sim/session_run.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kMaxTaskBytes = 1u << 20;
constexpr size_t kDrill = 0;  // PenRole::Drill's index in SessionStep's arrays
constexpr double kCavityTimePoints = 25.0;  // a cavity's time part at its most (docs/SCORING.md, section 5) [points]

nlohmann::ordered_json axisJson(const Vec3& axis) {
  const Vec3 a = axisForTaskFile(axis);
  return nlohmann::ordered_json::array({a.x, a.y, a.z});
}

// What the professional's session says, on a tooth of these axes.
ProfessionalFigures professionalFigures(const SessionRecording& session, const Task& task, const ToothAxes& axes) {
  const SessionStats stats = sessionStats(session, task);
  ProfessionalFigures p;
  p.elapsed_s = stats.elapsed_s;
  p.contact_s = stats.rate_hz > 0 ? double(stats.contact_samples) / stats.rate_hz : 0.0;
  p.drill_tool = session.info.drill_tool;
  p.bur_axis = meanCuttingBurAxis(session);
  if (p.bur_axis) p.bur_axis_from_crown_deg = angleDeg(*p.bur_axis, Vec3{axes.crown[0], axes.crown[1], axes.crown[2]});
  return p;
}

// Sets the keys the task's from_ideal lists in `root` (and `task`) from the professional's figures;
// says in `out` what was set and what was kept.
void applyFromIdeal(const ProfessionalFigures& pro, const ToothAxes& axes, Task& task, nlohmann::ordered_json& root,
                    IdealRecord& out) {
  if (task.from_ideal.insertion_axis) {
    if (!pro.bur_axis) {
      out.axis_kept_reason = "the professional's bur never cut (no step in contact with the pedal down)";
    } else {
      Task moved = task;
      moved.insertion_axis = *pro.bur_axis;
      if (auto problem = checkInsertionAxis(moved, axes)) {
        out.axis_kept_reason = "the professional's mean bur axis " + *problem;
      } else {
        root["insertion_axis"] = axisJson(*pro.bur_axis);
        task.insertion_axis = *pro.bur_axis;
        out.axis_set = true;
      }
    }
  }
  if (task.from_ideal.target_s && pro.elapsed_s > 0) {
    task = timedFromProfessional(std::move(task), pro.elapsed_s);
    root["target_s"] = task.target_s;
    if (hasFailureTime(taskKindRow(task.kind))) {
      root["failure_s"] = task.failure_s;
    } else if (std::string(taskKindRow(task.kind).coefficients) == "cavity") {  // a crown's score has no time part
      if (!root.contains("cavity")) root["cavity"] = nlohmann::ordered_json::object();
      root["cavity"]["time_coefficient"] = task.cavity.time_coefficient;
    }
    out.times_set = true;
  }
}

}  // namespace

Task timedFromProfessional(Task task, double professional_elapsed_s) {
  assert(professional_elapsed_s > 0);
  task.target_s = kTargetFactor * professional_elapsed_s;
  if (hasFailureTime(taskKindRow(task.kind)))
    task.failure_s = kFailureFactor * professional_elapsed_s;
  else
    // time_coefficient is points a minute [points/min]: all of them lost between the two times.
    task.cavity.time_coefficient = kCavityTimePoints * 60.0 / ((kFailureFactor - kTargetFactor) * professional_elapsed_s);
  return task;
}

std::optional<Vec3> meanCuttingBurAxis(const SessionRecording& session) {
  Vec3 sum{0, 0, 0};
  bool any = false;
  for (const SessionStep& step : session.steps) {
    if (!step.hasReading(kDrill) || step.contacts[kDrill] == 0 || !(step.reading[kDrill].pedal > 0)) continue;
    sum = sum + step.reading[kDrill].grip.rotation.rotate(Vec3{0, 0, 1});
    any = true;
  }
  if (!any || !(norm(sum) > 1e-9)) return std::nullopt;
  return normalized(sum);
}

Status checkIdealIdentity(const IdealSpec& ideal, const ToothVolume& initial, const std::string& where) {
  if (!ideal.initial_hash.empty()) {
    const std::string hash = volumeHashHex(initial.voxels, initial.frame);
    if (hash != ideal.initial_hash)
      return makeError(where, "recorded on another tooth (hash " + ideal.initial_hash + "), but this tooth's hash is " +
                                  hash + ": record the ideal again on this tooth (dentsim task set-ideal)");
  }
  if (ideal.kind == IdealKind::Session && !ideal.session_hash.empty()) {
    auto hash = fileHash(ideal.path);
    if (!hash) return hash.error();
    if (hashHex(*hash) != ideal.session_hash)
      return makeError(ideal.path, "the professional's session changed since it was recorded as the ideal (hash " +
                                       hashHex(*hash) + ", recorded " + ideal.session_hash + ")");
  }
  return Ok{};
}

Result<IdealRecord> setTaskIdeal(const std::string& task_path, const std::string& session_path,
                                 const std::string& final_tooth_path) {
  auto bytes = readFileBytes(task_path, kMaxTaskBytes);
  if (!bytes) return bytes.error();
  const std::string text(bytes->begin(), bytes->end());
  if (auto parsed = parseTask(text, task_path); !parsed) return parsed.error();
  // The same JSON, in its own key order, to change only "ideal".
  nlohmann::ordered_json root = nlohmann::ordered_json::parse(text);
  if (root.value("version", 0) != 2)
    return makeError(task_path, "a version 1 task file: set-ideal writes version 2 only (docs/SCORING.md, section 10)");
  auto task = builtinTask(task_path);  // the tooth's path resolved against the task's folder
  if (!task) return task.error();

  auto session = readSessionFile(session_path);
  if (!session) return session.error();
  if (!session->truncation_warning.empty()) return makeError(session_path, session->truncation_warning);
  if (!session->end) return makeError(session_path, "the session has no end record (it was cut short): record it again");

  // The session must start on the task's own tooth, or the ideal would be scored against another.
  const int level = isBuiltinTooth(task->tooth) ? builtinToothLevel(session->info.tooth_source, task->tooth) : 0;
  if (isBuiltinTooth(task->tooth) && level == 0)
    return makeError(session_path, "recorded on \"" + session->info.tooth_source + "\", not on the task's tooth, " + task->tooth);
  auto initial = taskTooth(*task, level);
  if (!initial) return initial.error();
  const std::string initial_hash = volumeHashHex(initial->voxels, initial->frame);
  if (session->info.tooth_hash != initial_hash)
    return makeError(session_path, "recorded on another tooth (hash " + session->info.tooth_hash + ") than the task's " +
                                       task->tooth + " (hash " + initial_hash + ")");

  ToothVolume final_tooth;
  if (!final_tooth_path.empty()) {
    auto loaded = loadTooth(final_tooth_path);
    if (!loaded) return loaded.error();
    final_tooth = std::move(*loaded);
  } else {
    final_tooth = *initial;
    auto replayed = replaySession(*session, final_tooth, ReplayOptions{});
    if (!replayed) return replayed.error();
  }
  const std::string final_hash = volumeHashHex(final_tooth.voxels, final_tooth.frame);
  if (final_hash != session->end->final_hash)
    return makeError(final_tooth_path.empty() ? session_path : final_tooth_path,
                     "not the session's final tooth (hash " + final_hash + ", the session ended on " +
                         session->end->final_hash + ")");
  if (final_hash == initial_hash)
    return makeError(session_path, "the session removed nothing: an ideal must cut the tooth");

  // The professional's figures, and the keys the task leaves to them, before anything is written.
  IdealRecord out;
  out.professional = professionalFigures(*session, *task, initial->frame.tooth);
  Task written_task = *task;
  applyFromIdeal(out.professional, initial->frame.tooth, written_task, root, out);

  const fs::path folder = fs::path(task_path).parent_path();
  const std::string stem = fs::path(task_path).stem().string();
  out.task_file = task_path;
  out.session_file = (folder / (stem + ".ideal.dses")).string();
  out.final_file = (folder / (stem + ".ideal.dvol")).string();
  if (sameFile(final_tooth_path, out.session_file) || sameFile(session_path, out.final_file) || sameFile(session_path, task_path) ||
      sameFile(final_tooth_path, task_path))
    return makeError(task_path, "the session or final tooth given is the file set-ideal writes");
  if (Status st = copyFileAtomic(session_path, out.session_file); !st) return st.error();
  if (Status st = saveTooth(out.final_file, final_tooth); !st) return st.error();
  auto session_hash = fileHash(out.session_file);
  if (!session_hash) return session_hash.error();

  out.spec.kind = IdealKind::Session;
  out.spec.path = stem + ".ideal.dses";
  out.spec.final_path = stem + ".ideal.dvol";
  out.spec.initial_hash = initial_hash;
  out.spec.final_hash = final_hash;
  out.spec.session_hash = hashHex(*session_hash);
  root["ideal"] = idealJson(out.spec);
  auto written = writeTaskFile(task_path, root);
  if (!written) return written.error();
  out.task = std::move(*written);
  return out;
}

}  // namespace dentsim
