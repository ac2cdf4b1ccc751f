// Parameter presets as JSON: the file's header (format, version, sections) and field tables that read and write one struct's numbers.
//
// Contents
//   1. The preset file: format, version, its top-level sections, size limit, text
//   2. Field tables: JSON key, member, allowed range
//   3. FieldReader: one-line errors "<path>: <problem>"
//   4. Reading a whole preset: strict JSON, the header, a stage's sections, "<where>: <path>: <problem>"
//
// A preset ("dentsim-params", docs/HAPTICS.md) is one JSON object whose sections belong to two stages:
// sim reads and writes the tactile ones (sim/sim_params.h), render the look of tissues and the view
// (render/look_params.h). Each stage's reader accepts, and skips, the other's sections, so either
// can read a whole preset; the UI and the app compose both into one file.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "io/strict_json.h"

namespace dentsim {

// ---- 1. the preset file ------------------------------------------------------------------------------

inline constexpr const char* kPresetFormat = "dentsim-params";
inline constexpr int kPresetVersion = 1;
inline constexpr uint64_t kMaxPresetBytes = 1u << 20;  // a preset is a few kB; anything near 1 MiB is not one

// Every top-level key, in file order: sim's sections, then render's ("looks", "view").
const std::vector<std::string>& presetTopKeys();

// {"format": "dentsim-params", "version": 1}; the stages append their sections in file order.
nlohmann::ordered_json presetHeaderJson();
// The file's text: 2-space indent, numbers as text that reads back bit-identical, a trailing newline.
// Non-finite numbers become null (which the readers reject); bad UTF-8 in a key is replaced.
std::string presetText(const nlohmann::ordered_json& root);

// ---- 2. field tables ---------------------------------------------------------------------------------

// An allowed interval; `text` completes "<value> is not ...".
struct Range {
  double lo, hi;
  bool lo_closed, hi_closed;
  const char* text;
  bool contains(double v) const { return (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi); }
};

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
inline constexpr Range kPositive{0.0, kInfinity, false, false, "> 0"};
inline constexpr Range kNonNegative{0.0, kInfinity, true, false, ">= 0"};
inline constexpr Range kUnit{0.0, 1.0, true, true, "in [0, 1]"};
inline constexpr Range kAnyNumber{-kInfinity, kInfinity, false, false, "finite"};

// One number in a JSON object: its key (the C++ member's name), the member, and its range.
template <class S>
struct Field {
  const char* key;
  double S::*member;
  Range range;
};

// Every field of the table equal (==, so 0 equals -0 and NaN equals nothing).
template <class S, size_t N>
bool sameFields(const S& a, const S& b, const Field<S> (&table)[N]) {
  for (const Field<S>& f : table)
    if (a.*(f.member) != b.*(f.member)) return false;
  return true;
}

// The table's keys, in table order.
template <class S, size_t N>
std::vector<std::string> fieldKeys(const Field<S> (&table)[N]) {
  std::vector<std::string> keys;
  for (const Field<S>& f : table) keys.emplace_back(f.key);
  return keys;
}

// Every field of the table, in table order.
template <class S, size_t N>
nlohmann::ordered_json fieldsJson(const S& s, const Field<S> (&table)[N]) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const Field<S>& f : table) j[f.key] = s.*(f.member);
  return j;
}

// ---- 3. reading --------------------------------------------------------------------------------------

// Checks parsed JSON against field tables and keeps the first error as "<path>: <problem>".
class FieldReader : public JsonSchemaReader {
 public:
  // Overrides the fields that `j` names; the rest keep their values.
  template <class S, size_t N>
  bool fields(const nlohmann::json& j, const std::string& path, const Field<S> (&table)[N], S* out) {
    if (!object(j, path, fieldKeys(table))) return false;
    for (const Field<S>& f : table) {
      auto it = j.find(f.key);
      if (it == j.end()) continue;
      if (!number(*it, jsonChildPath(path, f.key), f.range, &(out->*(f.member)))) return false;
    }
    return true;
  }

  // The object root[key] over *out; a missing section keeps the values.
  template <class S, size_t N>
  bool section(const nlohmann::json& root, const char* key, const Field<S> (&table)[N], S* out) {
    auto it = root.find(key);
    return it == root.end() || fields(*it, key, table, out);
  }

  // A finite number within `range`.
  bool number(const nlohmann::json& v, const std::string& path, const Range& range, double* out);

  // The preset's header: an object with "format" "dentsim-params", "version" 1 (checked first, so
  // that another JSON file is named as such), and no key outside presetTopKeys().
  bool presetHeader(const nlohmann::json& root);

  // A section with one object per name (a tissue's name), each overriding the fields it names: the
  // object at root[section][names[i]] goes to *slot(i). A missing section or name keeps the values.
  template <class S, size_t N, class Slot>
  bool namedFields(const nlohmann::json& root, const char* section, const std::vector<std::string>& names,
                   const Field<S> (&table)[N], Slot slot) {
    auto it = root.find(section);
    if (it == root.end()) return true;
    if (!object(*it, section, names)) return false;
    for (size_t i = 0; i < names.size(); ++i) {
      auto t = it->find(names[i]);
      if (t != it->end() && !fields(*t, jsonChildPath(section, names[i]), table, slot(i))) return false;
    }
    return true;
  }
};

// ---- 4. reading a whole preset -----------------------------------------------------------------------

// Reads the stages' sections of one preset; the first problem stays in the reader.
using PresetSections = std::function<void(const nlohmann::json& root, FieldReader& reader)>;

// The one preset reader that parseSimParams, parseLookParams and parsePreset share: parses
// `json_text` as strict JSON, checks the header, then calls `sections` (which writes over values the
// caller set to its defaults). Every problem is one line naming `where` and the key ("default.json:
// tissues.enamel.hardness: 1.5 is not in [0, 1]"). Never throws: a preset must never take the caller down.
Status readPreset(const std::string& json_text, const std::string& where, const PresetSections& sections);

}  // namespace dentsim
