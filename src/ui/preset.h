// Preset: a whole parameter preset file, sim's tactile sections and render's look and view, read and written as one.
//
// The file's format is one ("dentsim-params", version 1, docs/HAPTICS.md); its sections belong to two
// stages (io/param_fields.h). This is where they meet: the preset store, `--params` and the session
// recording use it, so a preset and a session header hold the same text they always did.
#pragma once

#include <string>

#include "core/result.h"
#include "render/look_params.h"
#include "sim/sim_params.h"

namespace dentsim::ui {

struct Preset {
  SimParams sim;     // the tactile sections: tissues, burs, turbine, cutting, coupling, device, point_shell
  LookParams looks;  // the visual sections: looks, view
};

// dentsim's defaults (the content of assets/presets/default.json).
Preset defaultPreset();
// Parses a whole preset: the header, then sim's sections, then render's, in file order, so the first
// problem is the one a reader of the file meets first. Errors are one line naming `where` and the key
// ("default.json: tissues.enamel.hardness: 1.5 is not in [0, 1]"). Never throws.
Result<Preset> parsePreset(const std::string& json_text, const std::string& where);
// Reads and parses a preset file (at most 1 MiB); errors name the path.
Result<Preset> loadPreset(const std::string& path);
// The preset as JSON: every field, keys in the fixed order, numbers that read back bit-identical, a
// trailing newline. parsePreset reads it back equal.
std::string presetJson(const Preset& preset);
// Writes the preset atomically; refuses (writing nothing) one that parsePreset would reject.
Status savePreset(const std::string& path, const Preset& preset);

bool operator==(const Preset& a, const Preset& b);

}  // namespace dentsim::ui
