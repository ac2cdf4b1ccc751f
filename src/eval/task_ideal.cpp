// setTaskIdeal and checkIdealIdentity: the professional's session copied beside the task, the task's "ideal" rewritten with its hashes.
#include "eval/task_ideal.h"

#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "eval/beside_file.h"
#include "eval/cut_score.h"
#include "eval/task_tooth.h"
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

}  // namespace

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
  const int level = task->tooth == kBuiltinMolarTooth ? builtinToothLevel(session->info.tooth_source) : 0;
  if (task->tooth == kBuiltinMolarTooth && level == 0)
    return makeError(session_path, "recorded on \"" + session->info.tooth_source + "\", not on the task's tooth, the built-in molar");
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

  const fs::path folder = fs::path(task_path).parent_path();
  const std::string stem = fs::path(task_path).stem().string();
  IdealRecord out;
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
  root["ideal"] = nlohmann::ordered_json{{"kind", "session"},
                                         {"path", out.spec.path},
                                         {"final", out.spec.final_path},
                                         {"initial_hash", out.spec.initial_hash},
                                         {"final_hash", out.spec.final_hash},
                                         {"session_hash", out.spec.session_hash}};
  const std::string written = root.dump(2) + "\n";
  if (auto check = parseTask(written, task_path); !check) return check.error();
  if (Status st = writeFileAtomic(task_path, written); !st) return st.error();
  return out;
}

}  // namespace dentsim
