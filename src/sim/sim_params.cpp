// SimParams presets: the defaults, and the JSON reader and writer, both driven by one field table per struct.
//
// Contents
//   1. Field tables: JSON key, member, allowed range (one place decides names, order and limits)
//   2. Defaults
//   3. Writing
//   4. Reading: the tactile sections (io/param_fields.h checks the header), parseSimParams, loadSimParams
//   5. Saving and equality
#include "sim/sim_params.h"

#include <iterator>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/strict_json.h"
#include "model/tool_generator.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

// ---- 1. field tables -----------------------------------------------------------------------------------

constexpr Range kFriction{0.0, 2.0, true, true, "in [0, 2]"};
constexpr Range kRpm{0.0, 1e6, false, true, "in (0, 1e6]"};
constexpr Range kReach{0.0, 1.0, true, true, "in [0, 1]"};
constexpr Range kStaleMs{0.0, 100.0, false, true, "in (0, 100]"};
constexpr Range kRateHz{100.0, 10000.0, true, true, "in [100, 10000]"};
constexpr Range kBudget{0.0, 0.9, false, true, "in (0, 0.9]"};
constexpr Range kForceChange{0.0, 1000.0, false, true, "in (0, 1000]"};
constexpr Range kSpacing{0.001, 1.0, true, true, "in [0.001, 1]"};

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
    {"contact_budget", &DeviceParams::contact_budget, kBudget},
    {"cut_budget", &DeviceParams::cut_budget, kBudget},
    {"max_force_change_n_per_ms", &DeviceParams::max_force_change_n_per_ms, kForceChange},
};
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
  }
  // Every built-in bur cuts; the handpiece and the mirror are not burs.
  for (const ToolSpec& t : toolCatalog()) {
    if (t.kind == ToolKind::RoundBur) p.burs[t.name].cutting_ability = 0.8;
    if (t.kind == ToolKind::FissureBur) p.burs[t.name].cutting_ability = 0.9;
    // Diamond grit abrades enamel readily but clogs sooner than a carbide's blades: as a round bur.
    if (t.kind == ToolKind::ChamferBur || t.kind == ToolKind::ShoulderBur) p.burs[t.name].cutting_ability = 0.8;
  }
  return p;
}

// ---- 3. writing ----------------------------------------------------------------------------------------

void appendSimParamsJson(const SimParams& params, ordered_json* root) {
  ordered_json tissues = ordered_json::object();
  for (Material m : kTissues) tissues[materialName(m)] = fieldsJson(params.tissue(m), kTissueFields);
  (*root)["tissues"] = std::move(tissues);
  ordered_json burs = ordered_json::object();  // std::map order: sorted by name
  for (const auto& [name, bur] : params.burs) burs[name] = fieldsJson(bur, kBurFields);
  (*root)["burs"] = std::move(burs);
  (*root)["turbine"] = fieldsJson(params.turbine, kTurbineFields);
  (*root)["cutting"] = fieldsJson(params.cutting, kCuttingFields);
  (*root)["coupling"] = fieldsJson(params.coupling, kCouplingFields);
  (*root)["device"] = fieldsJson(params.device, kDeviceFields);
  (*root)["point_shell"] = fieldsJson(params.point_shell, kPointShellFields);
}

std::string simParamsJson(const SimParams& params) {
  ordered_json root = presetHeaderJson();
  appendSimParamsJson(params, &root);
  return presetText(root);
}

// ---- 4. reading ----------------------------------------------------------------------------------------

// Each section in file order; "looks" and "view" are render's.
void readSimParamsJson(const json& root, FieldReader& r, SimParams* p) {
  if (!r.namedFields(root, "tissues", tissueKeys(), kTissueFields,
                     [&](size_t i) { return &p->tissue(kTissues[i]); }))
    return;
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
  if (!r.section(root, "turbine", kTurbineFields, &p->turbine)) return;
  if (!r.section(root, "cutting", kCuttingFields, &p->cutting)) return;
  if (!r.section(root, "coupling", kCouplingFields, &p->coupling)) return;
  if (!r.section(root, "device", kDeviceFields, &p->device)) return;
  r.section(root, "point_shell", kPointShellFields, &p->point_shell);
}

Result<SimParams> parseSimParams(const std::string& json_text, const std::string& where) {
  SimParams params = defaultSimParams();
  Status read =
      readPreset(json_text, where, [&](const json& root, FieldReader& r) { readSimParamsJson(root, r, &params); });
  if (!read) return read.error();
  return params;
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

bool operator==(const SimParams& a, const SimParams& b) {
  if (a.tissues != b.tissues) return false;
  if (a.burs.size() != b.burs.size()) return false;
  for (auto ia = a.burs.begin(), ib = b.burs.begin(); ia != a.burs.end(); ++ia, ++ib)
    if (ia->first != ib->first || !sameFields(ia->second, ib->second, kBurFields)) return false;
  return sameFields(a.turbine, b.turbine, kTurbineFields) && sameFields(a.cutting, b.cutting, kCuttingFields) &&
         sameFields(a.coupling, b.coupling, kCouplingFields) && sameFields(a.device, b.device, kDeviceFields) &&
         sameFields(a.point_shell, b.point_shell, kPointShellFields);
}

}  // namespace dentsim
