// SimParams: every tactile and cutting parameter a teacher can tune, with defaults, loaded from and saved to JSON presets.
//
// Contents
//   1. The parameter structs (units in brackets; defaults are dentsim's, hardness is the paper's)
//   2. Presets: parse, load, save, the built-in default
//
// The one set the haptic loop, the UI and the session file share. A preset is a readable JSON
// file (assets/presets/default.json is the default); docs/HAPTICS.md explains every field. The
// preset's "looks" and "view" sections are render's (render/look_params.h): these functions accept
// and skip them, and write only the tactile sections.
#pragma once

#include <array>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "io/param_fields.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. parameters -----------------------------------------------------------------------------------

// How one tissue feels and cuts. Contact force per shell point i (area a_i, penetration d_i, penetration
// rate v_i) is a_i * stiffness * d_i * (1 + damping * v_i) along the surface normal (Hunt-Crossley: the
// damping grows with depth, so contact starts without a jump and the energy lost depends on the speed
// at impact), plus friction * that normal force against the sliding direction.
struct TissueParams {
  double stiffness_n_per_mm3 = 0.0;  // spring per contact area per depth [N/mm^3], > 0 for tissue
  double damping_s_per_mm = 0.0;     // Hunt-Crossley damping [s/mm], >= 0
  double friction = 0.0;             // Coulomb coefficient against sliding [-], >= 0
  double hardness = 0.0;             // ease of cutting, the paper's "hardness" [0..1]
};

// A bur's cutting: removal scales with this, the tissue's hardness and the turbine speed.
struct BurParams {
  double cutting_ability = 0.0;  // [0..1]
};

// The turbine: the pedal sets speed in [0..1] of max_rpm.
struct TurbineParams {
  double max_rpm = 40000.0;  // speed at full pedal [1/min]
};

// Material removal: volume per second at hardness 1, ability 1 and full speed. Removed per step =
// removal_rate * hardness * ability * speed * dt, spread over the voxels under the cutting head.
struct CuttingParams {
  double removal_rate_mm3_per_s = 4.0;  // [mm^3/s] at hardness, ability and speed all 1
  double reach_mm = 0.02;               // a cutting point acts on voxels within this distance [mm]
};

// The virtual coupling between the pen (device) and the tool (proxy), and the proxy's own motion.
struct CouplingParams {
  double stiffness_n_per_mm = 1.0;           // device-to-proxy spring [N/mm]
  double damping_n_s_per_mm = 0.002;         // device-to-proxy damper [N s/mm]
  double rot_stiffness_n_mm_per_rad = 150.0; // rotational spring [N mm/rad]
  double rot_damping_n_mm_s_per_rad = 0.3;   // rotational damper [N mm s/rad]
  double proxy_damping_n_s_per_mm = 0.01;    // viscous drag on the proxy, implicit [N s/mm]
  double max_proxy_speed_mm_per_s = 200.0;   // the proxy never moves faster [mm/s]
};

// What the pen can display, and the loop's safety limits.
struct DeviceParams {
  double max_force_n = 8.0;          // force clamp, direction kept [N]
  double max_torque_n_mm = 0.0;      // torque clamp [N mm]; 0 for pens without torque output
  double stale_after_ms = 1.0;       // a force older than this is replaced by zero [ms]
  double rate_hz = 1000.0;           // haptic loop rate [Hz]
  // The step's own budget on the loop's thread (sim/haptic_loop.h), as fractions of the period: the
  // contact pass samples no further cluster after the first, and queued cuts start only before the
  // first and second sum. The rest of the period is the output's and the device driver's.
  double contact_budget = 0.05;      // of the period
  double cut_budget = 0.04;          // of the period, after the contact's
  double max_force_change_n_per_ms = 1.0;  // the force shown may change by this much a millisecond [N/ms]
};

// How tools become point shells.
struct PointShellParams {
  double head_spacing_mm = 0.03;   // point spacing on the cutting head [mm]
  double shank_spacing_mm = 0.08;  // point spacing on the neck and shank [mm]
  double mirror_spacing_mm = 0.3;  // point spacing on the mirror, which only collides [mm]
};

struct SimParams {
  std::array<TissueParams, DS_MATERIAL_COUNT> tissues{};  // indexed by Material; Empty and spare codes unused
  std::map<std::string, BurParams> burs;                  // by tool name ("round_bur_010")
  TurbineParams turbine;
  CuttingParams cutting;
  CouplingParams coupling;
  DeviceParams device;
  PointShellParams point_shell;

  TissueParams& tissue(Material m) { return tissues[size_t(m)]; }
  const TissueParams& tissue(Material m) const { return tissues[size_t(m)]; }
  // The bur's cutting ability; 0 for an unknown bur (it collides but does not cut).
  double cuttingAbility(const std::string& bur) const {
    auto it = burs.find(bur);
    return it == burs.end() ? 0.0 : it->second.cutting_ability;
  }
};

// ---- 2. presets --------------------------------------------------------------------------------------

// dentsim's defaults: each tissue's touch from the tissue table (volume/tissue_table.h; the paper's
// hardness), and an ability for every built-in bur.
SimParams defaultSimParams();

// Parses a preset. "format" ("dentsim-params") and "version" (1) are required; other keys left out
// keep their defaults, and "burs" entries merge into the default map (a new bur name is allowed).
// "looks" and "view" are accepted and not read (render/look_params.h reads them).
// Invalid JSON, an unknown or repeated key, a wrong type, a non-finite number or a value out of range
// is a one-line error naming `where` and the key ("default.json: tissues.enamel.hardness: 1.5 is not
// in [0, 1]"). Never throws.
Result<SimParams> parseSimParams(const std::string& json_text, const std::string& where);
// Reads and parses a preset file (at most 1 MiB); errors name the path.
Result<SimParams> loadSimParams(const std::string& path);
// The preset as JSON: 2-space indent, every field written, keys in a fixed order (burs by name),
// numbers as text that reads back bit-identical, a trailing newline. parseSimParams
// reads it back equal. Empty and the spare material codes are not written; neither are "looks" and
// "view" (a whole preset is ui/preset.h's presetJson).
std::string simParamsJson(const SimParams& params);
// The tactile sections, in file order, appended to `root` (a preset's header, io/param_fields.h).
void appendSimParamsJson(const SimParams& params, nlohmann::ordered_json* root);
// Reads the tactile sections of a preset whose header `r` has checked, over *params; the first
// problem stays in `r`.
void readSimParamsJson(const nlohmann::json& root, FieldReader& r, SimParams* params);
// Writes the preset atomically; refuses (writing nothing) one that parseSimParams would reject.
Status saveSimParams(const std::string& path, const SimParams& params);

// Field by field with == (so 0 equals -0, and a NaN equals nothing); SimParams compares all eight
// tissue slots.
bool operator==(const TissueParams& a, const TissueParams& b);
bool operator==(const SimParams& a, const SimParams& b);

}  // namespace dentsim
