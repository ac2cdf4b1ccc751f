// LookParams: the defaults from the tissue table, and the "looks" and "view" sections' field table, reader and writer.
#include "render/look_params.h"

#include <iterator>
#include <optional>
#include <vector>

#include "io/strict_json.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

constexpr Range kShininess{1.0, 512.0, true, true, "in [1, 512]"};

const Field<TissueLook> kLookFields[] = {
    {"ambient_r", &TissueLook::ambient_r, kUnit},   {"ambient_g", &TissueLook::ambient_g, kUnit},
    {"ambient_b", &TissueLook::ambient_b, kUnit},   {"diffuse_r", &TissueLook::diffuse_r, kUnit},
    {"diffuse_g", &TissueLook::diffuse_g, kUnit},   {"diffuse_b", &TissueLook::diffuse_b, kUnit},
    {"specular_r", &TissueLook::specular_r, kUnit}, {"specular_g", &TissueLook::specular_g, kUnit},
    {"specular_b", &TissueLook::specular_b, kUnit}, {"alpha", &TissueLook::alpha, kUnit},
    {"shininess", &TissueLook::shininess, kShininess},
};
// A field added to TissueLook must be added to the table, or presets would silently drop it.
static_assert(sizeof(TissueLook) == std::size(kLookFields) * sizeof(double));

// "view" holds one key, the normal mode as its neighbour count (a number, 216.0); read as a number
// and then checked against the modes, so that the table and its messages are the other sections'.
struct ViewFields {
  double normal_neighbours;  // 8, 64 or 216
};
const Field<ViewFields> kViewFields[] = {
    {"normal_neighbours", &ViewFields::normal_neighbours, kAnyNumber},
};

std::vector<std::string> tissueKeys() {
  std::vector<std::string> keys;
  for (Material m : kTissues) keys.push_back(materialName(m));
  return keys;
}

// {"normal_neighbours": 8, 64 or 216}; the section and the key may be left out.
bool readNormalMode(const json& root, FieldReader& r, NormalMode* out) {
  ViewFields view{double(normalNeighbours(*out))};
  if (!r.section(root, "view", kViewFields, &view)) return false;
  const std::optional<NormalMode> mode = normalModeFromNeighbours(view.normal_neighbours);
  if (!mode)
    return r.fail(jsonChildPath("view", "normal_neighbours"), json(view.normal_neighbours).dump() + " is not " +
                                                                  kNormalModeChoices);
  *out = *mode;
  return true;
}

}  // namespace

LookParams defaultLookParams() {
  LookParams p;
  for (const TissueRow& row : kTissueTable) {
    const TissueLookDefaults& l = row.look;
    p.look(row.material) = {l.ambient[0],  l.ambient[1],  l.ambient[2],  l.diffuse[0], l.diffuse[1], l.diffuse[2],
                            l.specular[0], l.specular[1], l.specular[2], l.alpha,      l.shininess};
  }
  return p;
}

void appendLookParamsJson(const LookParams& params, ordered_json* root) {
  ordered_json looks = ordered_json::object();
  for (Material m : kTissues) looks[materialName(m)] = fieldsJson(params.look(m), kLookFields);
  (*root)["looks"] = std::move(looks);
  (*root)["view"] = fieldsJson(ViewFields{double(normalNeighbours(params.view.normals))}, kViewFields);
}

void readLookParamsJson(const json& root, FieldReader& r, LookParams* p) {
  if (!r.namedFields(root, "looks", tissueKeys(), kLookFields, [&](size_t i) { return &p->look(kTissues[i]); }))
    return;
  readNormalMode(root, r, &p->view.normals);
}

Result<LookParams> parseLookParams(const std::string& json_text, const std::string& where) {
  LookParams params = defaultLookParams();
  Status read =
      readPreset(json_text, where, [&](const json& root, FieldReader& r) { readLookParamsJson(root, r, &params); });
  if (!read) return read.error();
  return params;
}

bool operator==(const TissueLook& a, const TissueLook& b) { return sameFields(a, b, kLookFields); }

bool operator==(const LookParams& a, const LookParams& b) {
  return a.looks == b.looks && a.view.normals == b.view.normals;
}

}  // namespace dentsim
