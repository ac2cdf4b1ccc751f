// The built-in teeth's names, a task's tooth and a session's starting tooth.
#include "eval/task_tooth.h"

#include <filesystem>
#include <system_error>

#include "eval/beside_file.h"

#include "model/builtin_assets.h"
#include "sim/builtin_tooth.h"
#include "volume/tooth_file.h"

namespace dentsim {

namespace {

// The built-in teeth by name (isBuiltinTooth's), each with what builds it.
struct BuiltinToothRow {
  const char* name;
  Result<ToothVolume> (*build)(int level);
};
constexpr BuiltinToothRow kBuiltinTeeth[] = {
    {kBuiltinMolarTooth, builtinMolarTooth},
    {kBuiltinMolarNeighboursTooth, builtinMolarNeighboursTooth},
};

}  // namespace

Result<ToothVolume> builtinTooth(const std::string& tooth, int level) {
  for (const BuiltinToothRow& row : kBuiltinTeeth)
    if (tooth == row.name) return row.build(level);
  return makeError(tooth, "not a built-in tooth (there are " + std::string(kBuiltinMolarTooth) + " and " +
                              kBuiltinMolarNeighboursTooth + ")");
}

int builtinToothLevel(const std::string& tooth_source, const std::string& tooth) {
  const std::string prefix = tooth + ":";
  if (tooth_source.rfind(prefix, 0) != 0) return 0;
  const std::string level = tooth_source.substr(prefix.size());
  if (level.empty() || level.size() > 2 || level.find_first_not_of("0123456789") != std::string::npos) return 0;
  return std::stoi(level);
}

Result<ToothVolume> loadToothFileOrAsset(const std::string& name) {
  for (const BuiltinToothRow& row : kBuiltinTeeth)
    if (const int level = builtinToothLevel(name, row.name); level > 0) return row.build(level);
  if (name.rfind(kAssetToothPrefix, 0) == 0) {
    const std::string asset = name.substr(std::string(kAssetToothPrefix).size());
    const std::span<const uint8_t> bytes = builtinAssetBytes(asset);
    if (bytes.empty()) return makeError(name, "not among the embedded assets");
    return parseTooth(bytes, "assets/" + asset);
  }
  return loadTooth(name);
}

Result<ToothVolume> taskTooth(const Task& task, int level) {
  if (isBuiltinTooth(task.tooth)) return builtinTooth(task.tooth, level > 0 ? level : task.level);
  return loadToothFileOrAsset(task.tooth);
}

Result<ToothVolume> resolveSessionTooth(const SessionRecording& session, const std::string& session_path,
                                        const std::string& override_path) {
  namespace fs = std::filesystem;
  if (!override_path.empty()) return loadTooth(override_path);
  const SessionInfo& info = session.info;
  if (!info.tooth_file.empty()) {
    // Only a file beside the session: a header naming /etc/passwd or ../../x is refused unread.
    auto beside = resolveBeside(session_path, info.tooth_file, "tooth.file");
    if (!beside) return beside.error();
    std::error_code ec;
    if (fs::exists(*beside, ec)) return loadTooth(*beside);
  }
  for (const BuiltinToothRow& row : kBuiltinTeeth)
    if (const int level = builtinToothLevel(info.tooth_source, row.name); level > 0) return row.build(level);
  return makeError(session_path, "cannot find the session's tooth (file \"" + info.tooth_file + "\", source \"" +
                                     info.tooth_source + "\"): give it with --tooth");
}

}  // namespace dentsim
