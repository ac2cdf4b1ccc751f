// PresetStore: the named parameter presets the panel offers: the built-in "default" plus the JSON files in a folder.
//
// A preset named N is the file <folder>/N.json, read and written by loadPreset / savePreset
// (ui/preset.h), so a preset saved here is the same file `dentsim run --params` reads. "default" is
// defaultPreset() (the content of assets/presets/default.json) and is read-only: a file named
// default.json in the folder is neither listed nor loaded, so the built-in set cannot be shadowed.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "ui/preset.h"

namespace dentsim::ui {

// The name of the built-in, read-only preset.
inline constexpr const char* kDefaultPresetName = "default";

// The folder presets live in by default: $XDG_CONFIG_HOME/dentsim/presets when XDG_CONFIG_HOME is
// set to an absolute path, else $HOME/.config/dentsim/presets; empty when neither is usable.
std::string defaultPresetDirectory();

// True for a name the store accepts: 1..64 of letters, digits, '_', '-', '.', not starting with '.'.
bool isValidPresetName(const std::string& name);

class PresetStore {
 public:
  // `directory` need not exist yet; it is created on the first save. Empty: saving is refused and
  // only "default" is listed.
  explicit PresetStore(std::string directory) : directory_(std::move(directory)) {}

  const std::string& directory() const { return directory_; }
  // The file a preset of this name lives in ("" for "default" and for invalid names).
  std::string pathOf(const std::string& name) const;

  // "default" first, then every valid <name>.json in the folder, sorted by name (byte order). A
  // missing or unreadable folder lists "default" alone.
  std::vector<std::string> list() const;
  // The preset's parameters. Errors are one line: an invalid name, or loadPreset's error (which
  // names the file: missing, unreadable, malformed, a value out of range).
  Result<Preset> load(const std::string& name) const;
  // Writes the preset atomically, creating the folder first when needed. Refuses an invalid name,
  // "default", and a set savePreset would reject; errors are one line naming the name or file.
  Status save(const std::string& name, const Preset& preset) const;

 private:
  std::string directory_;
};

}  // namespace dentsim::ui
