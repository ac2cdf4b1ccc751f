// LookParams: how the tissues look and how the tooth's surface is shaded, the preset's "looks" and "view" sections.
//
// Contents
//   1. The structs (units in brackets; defaults from the tissue table)
//   2. The preset's two sections: defaults, read, write, equality
//
// The visual half of a preset; sim's SimParams is the tactile half of the same file, and
// ui/preset.h reads and writes both as one. docs/HAPTICS.md explains every field.
#pragma once

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "io/param_fields.h"
#include "volume/brick_volume.h"
#include "volume/normal_mode.h"

namespace dentsim {

// ---- 1. the structs ----------------------------------------------------------------------------------

// How one tissue looks: Phong colours and opacity. The renderer draws opaque tissues first and the
// translucent ones (alpha < 1) over them, so a translucent enamel lets the dentin, pulp and caries
// beneath show through.
struct TissueLook {
  double ambient_r = 0.0, ambient_g = 0.0, ambient_b = 0.0;     // ambient colour [0..1]
  double diffuse_r = 0.0, diffuse_g = 0.0, diffuse_b = 0.0;     // diffuse colour [0..1]
  double specular_r = 0.0, specular_g = 0.0, specular_b = 0.0;  // specular colour [0..1]
  double alpha = 1.0;                                           // opacity [0..1]
  double shininess = 1.0;                                       // Phong exponent [1..512]
};

// The tooth's surface shading that is not per tissue.
struct ViewParams {
  NormalMode normals = NormalMode::Box216;  // preset key "normal_neighbours" (paper Fig. 15)
};

struct LookParams {
  std::array<TissueLook, DS_MATERIAL_COUNT> looks{};  // indexed by Material; Empty and spare codes unused
  ViewParams view;

  TissueLook& look(Material m) { return looks[size_t(m)]; }
  const TissueLook& look(Material m) const { return looks[size_t(m)]; }
};

// ---- 2. the preset's sections ------------------------------------------------------------------------

// dentsim's defaults: each tissue's look from the tissue table (volume/tissue_table.h), 216 neighbours.
LookParams defaultLookParams();

// "looks" (one object per tissue) and "view", appended to `root` after sim's sections.
void appendLookParamsJson(const LookParams& params, nlohmann::ordered_json* root);
// Reads "looks" and "view" of a preset whose header `r` has checked, over *params; keys left out keep
// their values, the tactile sections are skipped, and the first problem stays in `r`
// ("looks.pulp.alpha: 1.2 is not in [0, 1]").
void readLookParamsJson(const nlohmann::json& root, FieldReader& r, LookParams* params);
// Parses a whole preset's look and view over the defaults; errors are one line naming `where`.
Result<LookParams> parseLookParams(const std::string& json_text, const std::string& where);

// Field by field with == (so 0 equals -0, and a NaN equals nothing); all eight slots compared.
bool operator==(const TissueLook& a, const TissueLook& b);
bool operator==(const LookParams& a, const LookParams& b);

}  // namespace dentsim
