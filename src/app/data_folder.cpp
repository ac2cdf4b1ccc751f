// The installed dentsim's shared files, found relative to the executable (share/dentsim beside bin/).
#include "app/data_folder.h"

#include <filesystem>
#include <system_error>

#include "core/text_escape.h"

// cmake/Packaging.cmake defines it from the install directories (bin -> share/dentsim); the fallback
// is the same default, for a build that compiles this file without it.
#ifndef DENTSIM_DATA_FROM_BINDIR
#define DENTSIM_DATA_FROM_BINDIR "../share/dentsim"
#endif

namespace dentsim::app {

namespace fs = std::filesystem;

std::string executableFolder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

std::string installedDataFolder(const std::string& exe_folder) {
  if (exe_folder.empty()) return {};
  const fs::path data = (fs::path(exe_folder) / DENTSIM_DATA_FROM_BINDIR).lexically_normal();
  std::error_code ec;
  return fs::is_directory(data, ec) ? data.string() : std::string();
}

std::string installedCourseFolder(const std::string& exe_folder) {
  const std::string data = installedDataFolder(exe_folder);
  if (data.empty()) return {};
  const fs::path tasks = fs::path(data) / "tasks";
  std::error_code ec;
  return fs::is_directory(tasks, ec) ? tasks.string() : std::string();
}

std::string versionText(const std::string& exe_folder) {
  const std::string data = installedDataFolder(exe_folder);
  return std::string("dentsim ") + DENTSIM_VERSION + "\ndata: " +
         (data.empty() ? std::string("none beside this binary (built-in assets only)") : shownPath(data));
}

}  // namespace dentsim::app
