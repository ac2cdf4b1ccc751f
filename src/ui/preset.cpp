// Preset: composes sim's and render's sections of one preset file.
#include "ui/preset.h"

#include <exception>

#include "io/atomic_file.h"
#include "io/param_fields.h"
#include "io/strict_json.h"

namespace dentsim::ui {

Preset defaultPreset() { return Preset{defaultSimParams(), defaultLookParams()}; }

Result<Preset> parsePreset(const std::string& json_text, const std::string& where) {
  try {
    nlohmann::json root;
    std::string error;
    if (!parseStrictJson(json_text, &root, &error)) return makeError(where, error);
    Preset preset = defaultPreset();
    FieldReader reader;
    if (reader.presetHeader(root)) readSimParamsJson(root, reader, &preset.sim);
    if (!reader.failed()) readLookParamsJson(root, reader, &preset.looks);
    if (reader.failed()) return makeError(where, reader.error());
    return preset;
  } catch (const std::exception& e) {
    // Not reached for any input the tests know of; a preset must never take the caller down.
    return makeError(where, "cannot read preset: " + jsonExceptionText(e));
  }
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
