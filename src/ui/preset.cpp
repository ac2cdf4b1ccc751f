// Preset: composes sim's and render's sections of one preset file.
#include "ui/preset.h"

#include "io/atomic_file.h"
#include "io/param_fields.h"

namespace dentsim::ui {

Preset defaultPreset() { return Preset{defaultSimParams(), defaultLookParams()}; }

Result<Preset> parsePreset(const std::string& json_text, const std::string& where) {
  Preset preset = defaultPreset();
  // File order: sim's sections, then render's, so the first problem is the first a reader meets.
  Status read = readPreset(json_text, where, [&](const nlohmann::json& root, FieldReader& r) {
    readSimParamsJson(root, r, &preset.sim);
    if (!r.failed()) readLookParamsJson(root, r, &preset.looks);
  });
  if (!read) return read.error();
  return preset;
}

Result<Preset> loadPreset(const std::string& path) {
  auto bytes = readFileBytes(path, kMaxPresetBytes);
  if (!bytes) return bytes.error();
  return parsePreset(std::string(bytes->begin(), bytes->end()), path);
}

std::string presetJson(const Preset& preset) {
  nlohmann::ordered_json root = presetHeaderJson();
  appendSimParamsJson(preset.sim, &root);
  appendLookParamsJson(preset.looks, &root);
  return presetText(root);
}

Status savePreset(const std::string& path, const Preset& preset) {
  const std::string text = presetJson(preset);
  // Refuse to write what could not be read back (a value out of range, a bad bur name).
  if (auto check = parsePreset(text, ""); !check) return makeError(path, "not saved: " + check.message());
  return writeFileAtomic(path, text);
}

bool operator==(const Preset& a, const Preset& b) { return a.sim == b.sim && a.looks == b.looks; }

}  // namespace dentsim::ui
