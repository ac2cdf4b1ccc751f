// PresetStore: preset names to files in the preset folder, with the built-in default kept read-only.
#include "ui/preset_store.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "core/config_dir.h"

namespace dentsim::ui {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxNameLength = 64;
constexpr const char* kExtension = ".json";

bool isNameChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '.';
}

Error badName(const std::string& name) {
  return Error{"preset name '" + name + "' is not valid: use 1 to 64 letters, digits, '_', '-' or '.', not starting "
               "with '.'"};
}

}  // namespace

std::string defaultPresetDirectory() {
  const std::string dir = userConfigDir();
  return dir.empty() ? "" : dir + "/presets";
}

bool isValidPresetName(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameLength || name.front() == '.') return false;
  return std::all_of(name.begin(), name.end(), isNameChar);
}

std::string PresetStore::pathOf(const std::string& name) const {
  if (name == kDefaultPresetName || !isValidPresetName(name) || directory_.empty()) return "";
  return (fs::path(directory_) / (name + kExtension)).string();
}

std::vector<std::string> PresetStore::list() const {
  std::vector<std::string> names;
  if (!directory_.empty()) {
    std::error_code ec;
    // The non-throwing iterator: an unreadable entry ends the listing instead of throwing.
    for (fs::directory_iterator it(directory_, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      if (p.extension() != kExtension) continue;
      std::error_code type_ec;
      if (!it->is_regular_file(type_ec)) continue;
      std::string stem = p.stem().string();
      if (stem != kDefaultPresetName && isValidPresetName(stem)) names.push_back(std::move(stem));
    }
  }
  std::sort(names.begin(), names.end());
  names.insert(names.begin(), kDefaultPresetName);
  return names;
}

Result<Preset> PresetStore::load(const std::string& name) const {
  if (name == kDefaultPresetName) return defaultPreset();
  if (!isValidPresetName(name)) return badName(name);
  if (directory_.empty()) return Error{"preset '" + name + "': no preset folder (set HOME or XDG_CONFIG_HOME)"};
  return loadPreset(pathOf(name));
}

Status PresetStore::save(const std::string& name, const Preset& preset) const {
  if (name == kDefaultPresetName)
    return Error{"preset 'default' is built in and read-only: save under another name"};
  if (!isValidPresetName(name)) return badName(name);
  if (directory_.empty()) return Error{"preset '" + name + "': no preset folder (set HOME or XDG_CONFIG_HOME)"};
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec) return Error{"cannot create preset folder " + directory_ + ": " + ec.message()};
  return savePreset(pathOf(name), preset);
}

}  // namespace dentsim::ui
