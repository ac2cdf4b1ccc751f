// Parameter presets as JSON: the header check, the number check, the whole-preset reader and the file's text.
#include "io/param_fields.h"

#include <exception>

namespace dentsim {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

const std::vector<std::string>& presetTopKeys() {
  static const std::vector<std::string> keys = {"format",   "version", "tissues",     "burs",  "turbine", "cutting",
                                                "coupling", "device",  "point_shell", "looks", "view"};
  return keys;
}

ordered_json presetHeaderJson() {
  ordered_json root = ordered_json::object();
  root["format"] = kPresetFormat;
  root["version"] = kPresetVersion;
  return root;
}

std::string presetText(const ordered_json& root) {
  // nlohmann writes each double as short text that reads back bit-identical.
  return root.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

bool FieldReader::number(const json& v, const std::string& path, const Range& range, double* out) {
  if (!v.is_number()) return fail(path, std::string("expected a number, got ") + v.type_name());
  const double d = v.get<double>();
  // JSON has no NaN or infinity; a literal beyond the double range (1e999) reads as infinity.
  if (!std::isfinite(d)) return fail(path, "not a finite number");
  if (!range.contains(d)) return fail(path, v.dump() + " is not " + range.text);
  *out = d;
  return true;
}

bool FieldReader::presetHeader(const json& root) {
  if (!root.is_object()) return fail("", std::string("expected an object, got ") + root.type_name());
  auto format = root.find("format");
  if (format == root.end())
    return fail("format", std::string("missing; a preset starts with \"format\": \"") + kPresetFormat + "\"");
  if (!format->is_string()) return fail("format", std::string("expected a string, got ") + format->type_name());
  if (const std::string& f = format->get_ref<const std::string&>(); f != kPresetFormat)
    return fail("format", quotedForMessage(f) + " is not \"" + kPresetFormat + "\"");
  auto version = root.find("version");
  if (version == root.end()) return fail("version", "missing");
  if (!version->is_number_integer())
    return fail("version", std::string("expected an integer, got ") + version->type_name());
  // nlohmann reads every non-negative integer as unsigned.
  const bool supported = version->is_number_unsigned() ? version->get<uint64_t>() == uint64_t(kPresetVersion)
                                                       : version->get<int64_t>() == int64_t(kPresetVersion);
  if (!supported)
    return fail("version", version->dump() + " is not supported (this build reads version " +
                               std::to_string(kPresetVersion) + ")");
  return object(root, "", presetTopKeys());
}

Status readPreset(const std::string& json_text, const std::string& where, const PresetSections& sections) {
  try {
    json root;
    std::string error;
    if (!parseStrictJson(json_text, &root, &error)) return makeError(where, error);
    FieldReader reader;
    if (reader.presetHeader(root)) sections(root, reader);
    if (reader.failed()) return makeError(where, reader.error());
    return Ok{};
  } catch (const std::exception& e) {
    // Not reached for any input the tests know of.
    return makeError(where, "cannot read preset: " + jsonExceptionText(e));
  }
}

}  // namespace dentsim
