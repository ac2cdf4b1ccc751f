// The time stamp, a built-in tooth's name and a session's starting tooth, for the session commands.
#include "app/session_support.h"

#include <ctime>
#include <filesystem>

#include "sim/builtin_tooth.h"
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

}  // namespace dentsim::app
