// SimParams presets: the defaults, and the JSON reader and writer, both driven by one field table per struct.
//
// Contents
//   1. Field tables: JSON key, member, allowed range (one place decides names, order and limits)
//   2. Defaults
//   3. Writing
//   4. Reading: PresetReader (one-line errors "<where>: <path>: <problem>"), parseSimParams, loadSimParams
//   5. Saving and equality
#include "sim/sim_params.h"

#include "io/strict_json.h"

#include <cmath>
#include <exception>
#include <iterator>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "model/tool_generator.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

constexpr const char* kFormat = "dentsim-params";
constexpr int kVersion = 1;
constexpr uint64_t kMaxPresetBytes = 1u << 20;  // a preset is a few kB; anything near 1 MiB is not one

// ---- 1. field tables -----------------------------------------------------------------------------------

constexpr double kInf = std::numeric_limits<double>::infinity();

// An allowed interval; `text` completes "<value> is not ...".
struct Range {
  double lo, hi;
  bool lo_closed, hi_closed;
  const char* text;
  bool contains(double v) const {
    return (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
};

constexpr Range kPositive{0.0, kInf, false, false, "> 0"};
constexpr Range kNonNegative{0.0, kInf, true, false, ">= 0"};
constexpr Range kUnit{0.0, 1.0, true, true, "in [0, 1]"};
constexpr Range kFriction{0.0, 2.0, true, true, "in [0, 2]"};
constexpr Range kRpm{0.0, 1e6, false, true, "in (0, 1e6]"};
constexpr Range kReach{0.0, 1.0, true, true, "in [0, 1]"};
constexpr Range kStaleMs{0.0, 100.0, false, true, "in (0, 100]"};
constexpr Range kRateHz{100.0, 10000.0, true, true, "in [100, 10000]"};
constexpr Range kSpacing{0.001, 1.0, true, true, "in [0.001, 1]"};
constexpr Range kShininess{1.0, 512.0, true, true, "in [1, 512]"};
constexpr Range kAnyNumber{-kInf, kInf, false, false, "finite"};

// One number in a JSON object: its key (the C++ member's name), the member, and its range.
template <class S>
struct Field {
  const char* key;
  double S::*member;
  Range range;
};

const Field<TissueParams> kTissueFields[] = {
    {"stiffness_n_per_mm3", &TissueParams::stiffness_n_per_mm3, kPositive},
    {"damping_s_per_mm", &TissueParams::damping_s_per_mm, kNonNegative},
    {"friction", &TissueParams::friction, kFriction},
    {"hardness", &TissueParams::hardness, kUnit},
};
const Field<BurParams> kBurFields[] = {
    {"cutting_ability", &BurParams::cutting_ability, kUnit},
};
const Field<TurbineParams> kTurbineFields[] = {
    {"max_rpm", &TurbineParams::max_rpm, kRpm},
};
const Field<CuttingParams> kCuttingFields[] = {
    {"removal_rate_mm3_per_s", &CuttingParams::removal_rate_mm3_per_s, kNonNegative},
    {"reach_mm", &CuttingParams::reach_mm, kReach},
};
const Field<CouplingParams> kCouplingFields[] = {
    {"stiffness_n_per_mm", &CouplingParams::stiffness_n_per_mm, kPositive},
    {"damping_n_s_per_mm", &CouplingParams::damping_n_s_per_mm, kNonNegative},
    {"rot_stiffness_n_mm_per_rad", &CouplingParams::rot_stiffness_n_mm_per_rad, kPositive},
    {"rot_damping_n_mm_s_per_rad", &CouplingParams::rot_damping_n_mm_s_per_rad, kNonNegative},
    {"proxy_damping_n_s_per_mm", &CouplingParams::proxy_damping_n_s_per_mm, kNonNegative},
    {"max_proxy_speed_mm_per_s", &CouplingParams::max_proxy_speed_mm_per_s, kPositive},
};
const Field<DeviceParams> kDeviceFields[] = {
    {"max_force_n", &DeviceParams::max_force_n, kPositive},
    {"max_torque_n_mm", &DeviceParams::max_torque_n_mm, kNonNegative},
    {"stale_after_ms", &DeviceParams::stale_after_ms, kStaleMs},
    {"rate_hz", &DeviceParams::rate_hz, kRateHz},
};
const Field<TissueLook> kLookFields[] = {
    {"ambient_r", &TissueLook::ambient_r, kUnit},   {"ambient_g", &TissueLook::ambient_g, kUnit},
    {"ambient_b", &TissueLook::ambient_b, kUnit},   {"diffuse_r", &TissueLook::diffuse_r, kUnit},
    {"diffuse_g", &TissueLook::diffuse_g, kUnit},   {"diffuse_b", &TissueLook::diffuse_b, kUnit},
    {"specular_r", &TissueLook::specular_r, kUnit}, {"specular_g", &TissueLook::specular_g, kUnit},
    {"specular_b", &TissueLook::specular_b, kUnit}, {"alpha", &TissueLook::alpha, kUnit},
    {"shininess", &TissueLook::shininess, kShininess},
};
// "view" holds one key, the normal mode as its neighbour count (a number, 216.0).
const std::vector<std::string> kViewKeys = {"normal_neighbours"};
const Field<PointShellParams> kPointShellFields[] = {
    {"head_spacing_mm", &PointShellParams::head_spacing_mm, kSpacing},
    {"shank_spacing_mm", &PointShellParams::shank_spacing_mm, kSpacing},
    {"mirror_spacing_mm", &PointShellParams::mirror_spacing_mm, kSpacing},
};

// A field added to a struct must be added to its table, or presets would silently drop it.
static_assert(sizeof(TissueParams) == std::size(kTissueFields) * sizeof(double));
static_assert(sizeof(BurParams) == std::size(kBurFields) * sizeof(double));
static_assert(sizeof(TurbineParams) == std::size(kTurbineFields) * sizeof(double));
static_assert(sizeof(CuttingParams) == std::size(kCuttingFields) * sizeof(double));
static_assert(sizeof(CouplingParams) == std::size(kCouplingFields) * sizeof(double));
static_assert(sizeof(DeviceParams) == std::size(kDeviceFields) * sizeof(double));
static_assert(sizeof(PointShellParams) == std::size(kPointShellFields) * sizeof(double));
static_assert(sizeof(TissueLook) == std::size(kLookFields) * sizeof(double));

// Every field of the table equal (==, so 0 equals -0 and NaN equals nothing).
template <class S, size_t N>
bool sameFields(const S& a, const S& b, const Field<S> (&table)[N]) {
  for (const Field<S>& f : table)
    if (a.*(f.member) != b.*(f.member)) return false;
  return true;
}

// Top-level keys, in file order.
const std::vector<std::string> kTopKeys = {"format",   "version", "tissues",     "burs",  "turbine", "cutting",
                                           "coupling", "device",  "point_shell", "looks", "view"};

template <class S, size_t N>
std::vector<std::string> fieldKeys(const Field<S> (&fields)[N]) {
  std::vector<std::string> keys;
  for (const Field<S>& f : fields) keys.emplace_back(f.key);
  return keys;
}

std::vector<std::string> tissueKeys() {
  std::vector<std::string> keys;
  for (Material m : kTissues) keys.push_back(materialName(m));
  return keys;
}

}  // namespace

// ---- 2. defaults ---------------------------------------------------------------------------------------

SimParams defaultSimParams() {
  SimParams p;
  // The tissue table's defaults; a preset names each tissue by its row's name, in table order.
  for (const TissueRow& row : kTissueTable) {
    const TissueTouchDefaults& t = row.touch;
    p.tissue(row.material) = {t.stiffness_n_per_mm3, t.damping_s_per_mm, t.friction, t.hardness};
    const TissueLookDefaults& l = row.look;
    p.look(row.material) = {l.ambient[0],  l.ambient[1],  l.ambient[2],  l.diffuse[0], l.diffuse[1], l.diffuse[2],
                            l.specular[0], l.specular[1], l.specular[2], l.alpha,      l.shininess};
  }
  // Every built-in bur cuts; the handpiece and the mirror are not burs.
  for (const ToolSpec& t : toolCatalog()) {
    if (t.kind == ToolKind::RoundBur) p.burs[t.name].cutting_ability = 0.8;
    if (t.kind == ToolKind::FissureBur) p.burs[t.name].cutting_ability = 0.9;
  }
  return p;
}

// ---- 3. writing ----------------------------------------------------------------------------------------

namespace {

template <class S, size_t N>
ordered_json fieldsJson(const S& s, const Field<S> (&fields)[N]) {
  ordered_json j = ordered_json::object();
  for (const Field<S>& f : fields) j[f.key] = s.*(f.member);
  return j;
}

}  // namespace

std::string simParamsJson(const SimParams& params) {
  ordered_json root = ordered_json::object();
  root["format"] = kFormat;
  root["version"] = kVersion;
  ordered_json tissues = ordered_json::object();
  for (Material m : kTissues) tissues[materialName(m)] = fieldsJson(params.tissue(m), kTissueFields);
  root["tissues"] = std::move(tissues);
  ordered_json burs = ordered_json::object();  // std::map order: sorted by name
  for (const auto& [name, bur] : params.burs) burs[name] = fieldsJson(bur, kBurFields);
  root["burs"] = std::move(burs);
  root["turbine"] = fieldsJson(params.turbine, kTurbineFields);
  root["cutting"] = fieldsJson(params.cutting, kCuttingFields);
  root["coupling"] = fieldsJson(params.coupling, kCouplingFields);
  root["device"] = fieldsJson(params.device, kDeviceFields);
  root["point_shell"] = fieldsJson(params.point_shell, kPointShellFields);
  ordered_json looks = ordered_json::object();
  for (Material m : kTissues) looks[materialName(m)] = fieldsJson(params.look(m), kLookFields);
  root["looks"] = std::move(looks);
  ordered_json view = ordered_json::object();
  view["normal_neighbours"] = double(normalNeighbours(params.view.normals));
  root["view"] = std::move(view);
  // nlohmann writes each double as short text that reads back bit-identical; non-finite values become
  // null, which parseSimParams rejects. Bad UTF-8 in a bur name is replaced rather than thrown.
  return root.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

// ---- 4. reading ----------------------------------------------------------------------------------------

namespace {

// Checks parsed JSON against the schema and keeps the first error as "<path>: <problem>".
class PresetReader : public JsonSchemaReader {
 public:
  // Overrides the fields that `j` names; the rest keep their values.
  template <class S, size_t N>
  bool fields(const json& j, const std::string& path, const Field<S> (&table)[N], S* out) {
    if (!object(j, path, fieldKeys(table))) return false;
    for (const Field<S>& f : table) {
      auto it = j.find(f.key);
      if (it == j.end()) continue;
      if (!number(*it, jsonChildPath(path, f.key), f.range, &(out->*(f.member)))) return false;
    }
    return true;
  }

  // {"normal_neighbours": 8, 64 or 216}; the key may be left out.
  bool normalMode(const json& j, const std::string& path, NormalMode* out) {
    if (!object(j, path, kViewKeys)) return false;
    auto it = j.find("normal_neighbours");
    if (it == j.end()) return true;
    const std::string key = jsonChildPath(path, "normal_neighbours");
    double n = 0.0;
    if (!number(*it, key, kAnyNumber, &n)) return false;
    const std::optional<NormalMode> mode = normalModeFromNeighbours(n);
    if (!mode) return fail(key, json(n).dump() + " is not " + kNormalModeChoices);
    *out = *mode;
    return true;
  }

 private:
  bool number(const json& v, const std::string& path, const Range& range, double* out) {
    if (!v.is_number()) return fail(path, std::string("expected a number, got ") + v.type_name());
    const double d = v.get<double>();
    // JSON has no NaN or infinity; a literal beyond the double range (1e999) reads as infinity.
    if (!std::isfinite(d)) return fail(path, "not a finite number");
    if (!range.contains(d)) return fail(path, v.dump() + " is not " + range.text);
    *out = d;
    return true;
  }
};

// A section with one object per tissue ("tissues", "looks"), each overriding the fields it names.
template <class S, size_t N>
bool readPerTissue(const json& root, const char* section, const Field<S> (&fields)[N],
                   std::array<S, DS_MATERIAL_COUNT>& out, PresetReader& r) {
  auto it = root.find(section);
  if (it == root.end()) return true;
  if (!r.object(*it, section, tissueKeys())) return false;
  for (Material m : kTissues) {
    const std::string key = materialName(m);
    auto t = it->find(key);
    if (t != it->end() && !r.fields(*t, jsonChildPath(section, key), fields, &out[size_t(m)])) return false;
  }
  return true;
}

// The whole preset schema: format and version first (so that another JSON file is named as such),
// then each section in file order.
void readPreset(const json& root, PresetReader& r, SimParams* p) {
  if (!root.is_object()) {
    r.fail("", std::string("expected an object, got ") + root.type_name());
    return;
  }
  auto format = root.find("format");
  if (format == root.end()) {
    r.fail("format", std::string("missing; a preset starts with \"format\": \"") + kFormat + "\"");
    return;
  }
  if (!format->is_string()) {
    r.fail("format", std::string("expected a string, got ") + format->type_name());
    return;
  }
  if (const std::string& f = format->get_ref<const std::string&>(); f != kFormat) {
    r.fail("format", quotedForMessage(f) + " is not \"" + kFormat + "\"");
    return;
  }
  auto version = root.find("version");
  if (version == root.end()) {
    r.fail("version", "missing");
    return;
  }
  if (!version->is_number_integer()) {
    r.fail("version", std::string("expected an integer, got ") + version->type_name());
    return;
  }
  // nlohmann reads every non-negative integer as unsigned.
  const bool supported = version->is_number_unsigned() ? version->get<uint64_t>() == uint64_t(kVersion)
                                                       : version->get<int64_t>() == int64_t(kVersion);
  if (!supported) {
    r.fail("version", version->dump() + " is not supported (this build reads version " + std::to_string(kVersion) + ")");
    return;
  }
  if (!r.object(root, "", kTopKeys)) return;

  if (!readPerTissue(root, "tissues", kTissueFields, p->tissues, r)) return;
  // Bur entries merge into the defaults; a new bur name is allowed, so there is no list of known keys.
  if (auto it = root.find("burs"); it != root.end()) {
    if (!it->is_object()) {
      r.fail("burs", std::string("expected an object, got ") + it->type_name());
      return;
    }
    for (const auto& [name, value] : it->items()) {
      if (!isPlainName(name)) {
        r.fail(jsonChildPath("burs", name), "not a tool name (1 to 64 letters, digits, '_', '-', '.')");
        return;
      }
      auto known = p->burs.find(name);
      BurParams bur = known == p->burs.end() ? BurParams{} : known->second;
      if (!r.fields(value, jsonChildPath("burs", name), kBurFields, &bur)) return;
      p->burs[name] = bur;
    }
  }
  if (auto it = root.find("turbine"); it != root.end() && !r.fields(*it, "turbine", kTurbineFields, &p->turbine)) return;
  if (auto it = root.find("cutting"); it != root.end() && !r.fields(*it, "cutting", kCuttingFields, &p->cutting)) return;
  if (auto it = root.find("coupling"); it != root.end() && !r.fields(*it, "coupling", kCouplingFields, &p->coupling))
    return;
  if (auto it = root.find("device"); it != root.end() && !r.fields(*it, "device", kDeviceFields, &p->device)) return;
  if (auto it = root.find("point_shell"); it != root.end() && !r.fields(*it, "point_shell", kPointShellFields, &p->point_shell))
    return;
  if (!readPerTissue(root, "looks", kLookFields, p->looks, r)) return;
  if (auto it = root.find("view"); it != root.end()) r.normalMode(*it, "view", &p->view.normals);
}

}  // namespace

Result<SimParams> parseSimParams(const std::string& json_text, const std::string& where) {
  try {
    json root;
    std::string error;
    if (!parseStrictJson(json_text, &root, &error)) return makeError(where, error);
    SimParams params = defaultSimParams();
    PresetReader reader;
    readPreset(root, reader, &params);
    if (reader.failed()) return makeError(where, reader.error());
    return params;
  } catch (const std::exception& e) {
    // Not reached for any input the tests know of; a preset must never take the caller down.
    return makeError(where, "cannot read preset: " + jsonExceptionText(e));
  }
}

Result<SimParams> loadSimParams(const std::string& path) {
  auto bytes = readFileBytes(path, kMaxPresetBytes);
  if (!bytes) return bytes.error();
  return parseSimParams(std::string(bytes->begin(), bytes->end()), path);
}

// ---- 5. saving and equality ----------------------------------------------------------------------------

Status saveSimParams(const std::string& path, const SimParams& params) {
  const std::string text = simParamsJson(params);
  // Refuse to write what could not be read back (a value out of range, a bad bur name).
  if (auto check = parseSimParams(text, ""); !check) return makeError(path, "not saved: " + check.message());
  return writeFileAtomic(path, text);
}

bool operator==(const TissueParams& a, const TissueParams& b) { return sameFields(a, b, kTissueFields); }
bool operator==(const TissueLook& a, const TissueLook& b) { return sameFields(a, b, kLookFields); }

bool operator==(const SimParams& a, const SimParams& b) {
  if (a.tissues != b.tissues || a.looks != b.looks) return false;
  if (a.burs.size() != b.burs.size()) return false;
  for (auto ia = a.burs.begin(), ib = b.burs.begin(); ia != a.burs.end(); ++ia, ++ib)
    if (ia->first != ib->first || !sameFields(ia->second, ib->second, kBurFields)) return false;
  return sameFields(a.turbine, b.turbine, kTurbineFields) && sameFields(a.cutting, b.cutting, kCuttingFields) &&
         sameFields(a.coupling, b.coupling, kCouplingFields) && sameFields(a.device, b.device, kDeviceFields) &&
         sameFields(a.point_shell, b.point_shell, kPointShellFields) && a.view.normals == b.view.normals;
}

}  // namespace dentsim
