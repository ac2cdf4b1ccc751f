// Task files: the JSON reader, with one-line errors "<where>: <key path>: <problem>" like the parameter presets'.
#include "eval/task.h"

#include <cmath>
#include <exception>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/crown_targets.h"
#include "eval/task_kinds.h"
#include "io/atomic_file.h"
#include "io/strict_json.h"
#include "volume/brick_layout.h"

namespace dentsim {
namespace {

using json = nlohmann::json;

constexpr const char* kFormat = "dentsim-task";
constexpr int kVersion = 2;  // version 1 files are read too
constexpr uint64_t kMaxTaskBytes = 1u << 20;  // a task is under 1 kB

// Checks values against the schema and keeps the first problem as "<path>: <problem>".
class TaskReader : public JsonSchemaReader {
 public:
  // The member `key` of object j, or null (and an error when required) if absent.
  const json* member(const json& j, const std::string& path, const char* key, bool required) {
    auto it = j.find(key);
    if (it != j.end()) return &*it;
    if (required) fail(jsonChildPath(path, key), "missing");
    return nullptr;
  }

  // A finite number with lo < v (or lo <= v when lo_closed) and v <= hi.
  bool number(const json& j, const std::string& path, const char* key, bool required, double lo, bool lo_closed,
              double hi, const std::string& range_text, double* out) {
    const json* v = member(j, path, key, required);
    if (!v) return !failed();
    const std::string p = jsonChildPath(path, key);
    if (!v->is_number()) return fail(p, std::string("expected a number, got ") + v->type_name());
    const double d = v->get<double>();
    if (!std::isfinite(d)) return fail(p, "not a finite number");
    if (!(lo_closed ? d >= lo : d > lo) || !(d <= hi)) return fail(p, v->dump() + " is not " + range_text);
    *out = d;
    return true;
  }

  bool integer(const json& j, const std::string& path, const char* key, bool required, int lo, int hi, int* out) {
    const json* v = member(j, path, key, required);
    if (!v) return !failed();
    const std::string p = jsonChildPath(path, key);
    if (!v->is_number_integer()) return fail(p, std::string("expected an integer, got ") + v->type_name());
    const bool in_range = v->is_number_unsigned() ? v->get<uint64_t>() <= uint64_t(hi) && v->get<uint64_t>() >= uint64_t(lo)
                                                  : v->get<int64_t>() >= lo && v->get<int64_t>() <= hi;
    if (!in_range) return fail(p, v->dump() + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    *out = static_cast<int>(v->get<int64_t>());
    return true;
  }

  // A string; `name` true: it must be a file-stem name.
  bool string(const json& j, const std::string& path, const char* key, bool required, bool name, std::string* out) {
    const json* v = member(j, path, key, required);
    if (!v) return !failed();
    const std::string p = jsonChildPath(path, key);
    if (!v->is_string()) return fail(p, std::string("expected a string, got ") + v->type_name());
    const std::string& s = v->get_ref<const std::string&>();
    if (s.empty()) return fail(p, "empty");
    if (name && !isPlainName(s)) return fail(p, quotedForMessage(s) + " is not a name (1 to 64 letters, digits, '_', '-', '.')");
    *out = s;
    return true;
  }

  // One of `choices`; its index in *out.
  bool choice(const json& j, const std::string& path, const char* key, const std::vector<std::string>& choices,
              size_t* out) {
    std::string s;
    if (!string(j, path, key, true, false, &s)) return false;
    for (size_t i = 0; i < choices.size(); ++i)
      if (choices[i] == s) {
        *out = i;
        return true;
      }
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
    return fail(jsonChildPath(path, key), quotedForMessage(s) + " is not one of " + list);
  }

  // A band [lo, hi]: two finite numbers, each with bound < v (bound <= v when bound_closed) and
  // v <= top, and lo < hi.
  bool band(const json& j, const std::string& path, const char* key, double bound, bool bound_closed, double top,
            const std::string& range_text, double* lo, double* hi) {
    const json* v = member(j, path, key, false);
    if (!v) return !failed();
    const std::string p = jsonChildPath(path, key);
    if (!v->is_array() || v->size() != 2) return fail(p, "expected [lo, hi], an array of 2 numbers");
    double d[2];
    for (size_t i = 0; i < 2; ++i) {
      const json& e = (*v)[i];
      const std::string pi = p + "[" + std::to_string(i) + "]";
      if (!e.is_number()) return fail(pi, std::string("expected a number, got ") + e.type_name());
      d[i] = e.get<double>();
      if (!std::isfinite(d[i])) return fail(pi, "not a finite number");
      if (!(bound_closed ? d[i] >= bound : d[i] > bound) || !(d[i] <= top)) return fail(pi, e.dump() + " is not " + range_text);
    }
    if (!(d[0] < d[1])) return fail(p, "lo " + (*v)[0].dump() + " is not < hi " + (*v)[1].dump());
    *lo = d[0];
    *hi = d[1];
    return true;
  }

  // Three finite numbers, not all zero; normalized.
  bool direction(const json& j, const std::string& path, const char* key, Vec3* out) {
    const json* v = member(j, path, key, false);
    if (!v) return !failed();
    const std::string p = jsonChildPath(path, key);
    if (!v->is_array() || v->size() != 3) return fail(p, "expected an array of 3 numbers");
    Vec3 a;
    for (int i = 0; i < 3; ++i) {
      const json& e = (*v)[size_t(i)];
      if (!e.is_number() || !std::isfinite(e.get<double>())) return fail(p, "expected an array of 3 finite numbers");
      a[i] = e.get<double>();
    }
    if (!(norm(a) > 1e-9)) return fail(p, "zero vector; the axis needs a direction");
    *out = normalized(a);
    return true;
  }
};

constexpr double kHuge = 1e9;
const std::string kNonNegative = ">= 0 and <= 1e9";

// The ideal: {"kind": ..., "path": ...} at `path`.
bool readIdeal(const json& ideal, const std::string& path, TaskReader& r, IdealSpec* out) {
  if (!r.object(ideal, path, {"kind", "path", "final", "initial_hash", "final_hash", "session_hash"})) return false;
  size_t kind = 0;
  if (!r.choice(ideal, path, "kind", {"builtin_path", "volume", "session"}, &kind)) return false;
  out->kind = static_cast<IdealKind>(kind);
  if (!r.string(ideal, path, "path", true, false, &out->path)) return false;
  if (!r.string(ideal, path, "final", false, false, &out->final_path)) return false;
  if (!out->final_path.empty() && out->kind != IdealKind::Session)
    return r.fail(jsonChildPath(path, "final"), "only for kind \"session\"");
  for (auto [key, hash] : {std::pair{"initial_hash", &out->initial_hash}, {"final_hash", &out->final_hash},
                           {"session_hash", &out->session_hash}}) {
    if (!r.string(ideal, path, key, false, false, hash)) return false;
    if (!hash->empty() && (hash->size() != 16 || hash->find_first_not_of("0123456789abcdef") != std::string::npos))
      return r.fail(jsonChildPath(path, key), quotedForMessage(*hash) + " is not a hash (16 lower-case hex digits)");
  }
  return true;
}

// The first view: {"camera": preset, "elevation_deg": number, "fixed": bool}.
bool readView(const json& view, TaskReader& r, TaskView* out) {
  const std::string path = "view";
  if (!r.object(view, path, {"camera", "elevation_deg", "fixed"})) return false;
  size_t camera = 0;
  const std::vector<std::string> cameras = {"occlusal", "buccal", "lingual", "mesial", "distal"};
  if (!r.choice(view, path, "camera", cameras, &camera)) return false;
  out->camera = cameras[camera];
  if (!r.number(view, path, "elevation_deg", false, -89, true, 89, "in [-89, 89]", &out->elevation_deg)) return false;
  if (const json* fixed = r.member(view, path, "fixed", false)) {
    if (!fixed->is_boolean()) return r.fail(jsonChildPath(path, "fixed"), std::string("expected true or false, got ") + fixed->type_name());
    out->fixed = fixed->get<bool>();
  }
  return true;
}

// "from_ideal": the names of the keys set-ideal may set, each at most once.
bool readFromIdeal(const json& root, TaskReader& r, FromIdeal* out) {
  const json* v = r.member(root, "", "from_ideal", false);
  if (!v) return !r.failed();
  if (!v->is_array()) return r.fail("from_ideal", std::string("expected an array of key names, got ") + v->type_name());
  for (size_t i = 0; i < v->size(); ++i) {
    const json& e = (*v)[i];
    const std::string p = "from_ideal[" + std::to_string(i) + "]";
    if (!e.is_string()) return r.fail(p, std::string("expected a key name, got ") + e.type_name());
    const std::string& name = e.get_ref<const std::string&>();
    bool* flag = name == "insertion_axis" ? &out->insertion_axis : name == "target_s" ? &out->target_s : nullptr;
    if (!flag) return r.fail(p, quotedForMessage(name) + " is not one of \"insertion_axis\", \"target_s\"");
    if (*flag) return r.fail(p, quotedForMessage(name) + " is listed twice");
    *flag = true;
  }
  return true;
}

// The zone's keys (insertion_axis, leeway_mm, ideal) in object j at `path`: the root in version 2,
// "cavity" in version 1.
bool readZone(const json& j, const std::string& path, TaskReader& r, Task* t) {
  if (!r.direction(j, path, "insertion_axis", &t->insertion_axis)) return false;
  if (!r.number(j, path, "leeway_mm", false, 0, true, 1, "in [0, 1]", &t->leeway_mm)) return false;
  const json* ideal = r.member(j, path, "ideal", taskKindRow(t->kind).ideal_required);
  if (!ideal) return !r.failed();
  t->ideal.emplace();
  return readIdeal(*ideal, jsonChildPath(path, "ideal"), r, &*t->ideal);
}

// The cavity object's coefficients; version 1 also holds the zone's keys there.
void readCavity(const json& j, int version, TaskReader& r, Task* t) {
  const std::string path = "cavity";
  std::vector<std::string> keys = {"undercut_coefficient", "overcut_coefficient", "parallel_coefficient",
                                   "time_coefficient", "parallel_error_deg"};
  if (version == 1)
    keys.insert(keys.end(), {"insertion_axis", "leeway_mm", "ideal"});
  else
    keys.insert(keys.end(), {"force_coefficient", "near_overcut_weight"});
  if (!r.object(j, path, keys)) return;
  CavityTask* c = &t->cavity;
  if (!r.number(j, path, "undercut_coefficient", false, 0, true, kHuge, kNonNegative, &c->undercut_coefficient)) return;
  if (!r.number(j, path, "overcut_coefficient", false, 0, true, kHuge, kNonNegative, &c->overcut_coefficient)) return;
  if (!r.number(j, path, "parallel_coefficient", false, 0, true, kHuge, kNonNegative, &c->parallel_coefficient)) return;
  if (!r.number(j, path, "time_coefficient", false, 0, true, kHuge, kNonNegative, &c->time_coefficient)) return;
  if (!r.number(j, path, "force_coefficient", false, 0, true, kHuge, kNonNegative, &c->force_coefficient)) return;
  if (!r.number(j, path, "parallel_error_deg", false, 0, false, 90, "in (0, 90]", &c->parallel_error_deg)) return;
  if (!r.number(j, path, "near_overcut_weight", false, 0, true, 1, "in [0, 1]", &c->near_overcut_weight)) return;
  if (version == 1) readZone(j, path, r, t);
}

void readAccess(const json& j, TaskReader& r, Task* t) {
  const std::string path = "access";
  if (!r.object(j, path, {"unopened_cap"})) return;
  r.number(j, path, "unopened_cap", false, 0, true, 100, "in [0, 100]", &t->access.unopened_cap);
}

void readAdjacent(const json& j, TaskReader& r, Task* t) {
  const std::string path = "adjacent";
  if (!r.object(j, path, {"coefficient", "min_points", "noise_voxels"})) return;
  AdjacentTask* a = &t->adjacent;
  if (!r.number(j, path, "coefficient", false, 0, true, kHuge, kNonNegative, &a->coefficient)) return;
  if (!r.number(j, path, "min_points", false, 0, true, 100, "in [0, 100]", &a->min_points)) return;
  r.number(j, path, "noise_voxels", false, 0, true, kHuge, kNonNegative, &a->noise_voxels);
}

void readCaries(const json& j, TaskReader& r, Task* t) {
  const std::string path = "caries";
  if (!r.object(j, path, {"healthy_coefficient"})) return;
  r.number(j, path, "healthy_coefficient", false, 0, true, kHuge, kNonNegative, &t->caries.healthy_coefficient);
}

// The crown object: finish and material choose every band (eval/crown_targets.h), and each key
// given replaces its own. A file without the object is an all-ceramic crown on a chamfer.
void readCrown(const json& j, TaskReader& r, Task* t) {
  const std::string path = "crown";
  if (!r.object(j, path, {"finish", "material", "occlusal_mm", "axial_mm", "margin_width_mm", "toc_deg", "toc_near_deg",
                          "min_height_mm", "min_height_width_ratio", "margin_above_cej_mm", "undercut_tolerance_mm2",
                          "undercut_cap"}))
    return;
  std::vector<std::string> finishes, materials;
  for (const CrownFinishRow& row : kCrownFinishTable) finishes.push_back(row.name);
  for (const CrownMaterialRow& row : kCrownMaterialTable) materials.push_back(row.name);
  size_t finish = 0, material = 0;
  if (j.contains("finish") && !r.choice(j, path, "finish", finishes, &finish)) return;
  if (j.contains("material") && !r.choice(j, path, "material", materials, &material)) return;
  CrownTask* c = &t->crown;
  *c = crownTargets(kCrownFinishTable[finish], kCrownMaterialTable[material]);
  // A reduction or a margin beyond 10 mm is wider than a molar's crown: a slip of the decimal point.
  const std::string mm = "> 0 and <= 10";
  if (!r.band(j, path, "occlusal_mm", 0, false, 10, mm, &c->occlusal_lo_mm, &c->occlusal_hi_mm)) return;
  if (!r.band(j, path, "axial_mm", 0, false, 10, mm, &c->axial_lo_mm, &c->axial_hi_mm)) return;
  if (!r.band(j, path, "margin_width_mm", 0, false, 10, mm, &c->margin_lo_mm, &c->margin_hi_mm)) return;
  if (!r.band(j, path, "toc_deg", 0, true, 60, "in [0, 60]", &c->toc_lo_deg, &c->toc_hi_deg)) return;
  if (!r.band(j, path, "toc_near_deg", 0, true, 60, "in [0, 60]", &c->toc_near_lo_deg, &c->toc_near_hi_deg)) return;
  // Near is the recommended convergence widened: it must hold it. The key the file gave is named.
  if (!(c->toc_near_lo_deg <= c->toc_lo_deg && c->toc_hi_deg <= c->toc_near_hi_deg)) {
    const std::string toc = "[" + json(c->toc_lo_deg).dump() + ", " + json(c->toc_hi_deg).dump() + "]";
    const std::string near = "[" + json(c->toc_near_lo_deg).dump() + ", " + json(c->toc_near_hi_deg).dump() + "]";
    if (j.contains("toc_near_deg"))
      r.fail(jsonChildPath(path, "toc_near_deg"), near + " does not hold toc_deg " + toc);
    else
      r.fail(jsonChildPath(path, "toc_deg"), toc + " is not within toc_near_deg " + near + " (give toc_near_deg too)");
    return;
  }
  if (!r.number(j, path, "min_height_mm", false, 0, false, 20, "> 0 and <= 20", &c->min_height_mm)) return;
  if (!r.number(j, path, "min_height_width_ratio", false, 0, false, 10, "> 0 and <= 10", &c->min_height_width_ratio)) return;
  // Below zero: a subgingival margin, under the CEJ.
  if (!r.band(j, path, "margin_above_cej_mm", -10, true, 10, "in [-10, 10]", &c->margin_above_cej_lo_mm,
              &c->margin_above_cej_hi_mm))
    return;
  if (!r.number(j, path, "undercut_tolerance_mm2", false, 0, true, kHuge, kNonNegative, &c->undercut_tolerance_mm2)) return;
  r.number(j, path, "undercut_cap", false, 0, true, 100, "in [0, 100]", &c->undercut_cap);
}

// The kinds whose row passes `has`, quoted for a message: "\"caries\"", or "\"a\" or \"b\"".
template <typename RowTest>
std::string quotedKinds(RowTest has) {
  std::string out;
  for (const TaskKindRow& row : kTaskKindTable)
    if (has(row)) out += (out.empty() ? "" : " or ") + quotedForMessage(row.name);
  return out;
}

// The whole schema: format and version first, so that another JSON file is named as such.
void readTask(const json& root, TaskReader& r, Task* t) {
  if (!root.is_object()) {
    r.fail("", std::string("expected an object, got ") + root.type_name());
    return;
  }
  std::string format;
  if (!r.string(root, "", "format", true, false, &format)) return;
  if (format != kFormat) {
    r.fail("format", quotedForMessage(format) + " is not \"" + kFormat + "\"");
    return;
  }
  const json* version_json = r.member(root, "", "version", true);
  if (!version_json) return;
  if (!version_json->is_number_integer()) {
    r.fail("version", std::string("expected an integer, got ") + version_json->type_name());
    return;
  }
  const std::string version_text = version_json->dump();
  if (version_text != "1" && version_text != std::to_string(kVersion)) {
    r.fail("version", version_text + " is not supported (this build reads versions 1 to " + std::to_string(kVersion) + ")");
    return;
  }
  const int version = version_text == "1" ? 1 : kVersion;
  std::vector<std::string> keys = {"format",    "version",   "name",          "kind",  "title", "tooth", "level",
                                   "tools",     "target_s",  "failure_s",     "force_error_n", "cavity"};
  if (version >= 2)
    keys.insert(keys.end(), {"insertion_axis", "leeway_mm", "ideal", "pulp_exposure_cap", "caries", "instructions", "view", "access",
                             "pass_mark", "from_ideal", "cavity_class", "adjacent", "crown"});
  if (!r.object(root, "", keys)) return;
  if (!r.string(root, "", "name", true, true, &t->name)) return;
  std::vector<std::string> kinds;
  for (const TaskKindRow& row : kTaskKindTable) kinds.push_back(row.name);
  size_t kind = 0;
  if (!r.choice(root, "", "kind", kinds, &kind)) return;
  const TaskKindRow& row = kTaskKindTable[kind];
  if (version < row.since_version) {
    r.fail("kind", quotedForMessage(row.name) + " needs version " + std::to_string(row.since_version));
    return;
  }
  t->kind = row.kind;
  t->title = t->name;
  if (!r.string(root, "", "title", false, false, &t->title)) return;
  if (!r.string(root, "", "instructions", false, false, &t->instructions)) return;
  if (const json* view = r.member(root, "", "view", false)) {
    t->view.emplace();
    if (!readView(*view, r, &*t->view)) return;
  }
  if (!r.string(root, "", "tooth", true, false, &t->tooth)) return;
  if (!r.integer(root, "", "level", false, int(DS_MIN_LEVEL), int(DS_MAX_LEVEL), &t->level)) return;

  const json* tools = r.member(root, "", "tools", true);
  if (!tools || !r.object(*tools, "tools", {"drill", "mirror"})) return;
  if (!r.string(*tools, "tools", "drill", true, true, &t->drill_tool)) return;
  if (!r.string(*tools, "tools", "mirror", false, true, &t->mirror_tool)) return;

  if (!r.number(root, "", "target_s", true, 0, false, kHuge, "> 0 and <= 1e9", &t->target_s)) return;
  if (!r.number(root, "", "force_error_n", true, 0, false, kHuge, "> 0 and <= 1e9", &t->force_error_n)) return;
  if (version >= 2) {
    if (!r.number(root, "", "pulp_exposure_cap", false, 0, true, 100, "in [0, 100]", &t->pulp_exposure_cap)) return;
    if (!readZone(root, "", r, t)) return;
    if (!readFromIdeal(root, r, &t->from_ideal)) return;
    if (const json* adjacent = r.member(root, "", "adjacent", false)) {
      readAdjacent(*adjacent, r, t);
      if (r.failed()) return;
    }
    double pass_mark = 0.0;
    if (root.contains("pass_mark")) {
      if (!r.number(root, "", "pass_mark", true, 0, true, 100, "in [0, 100]", &pass_mark)) return;
      t->pass_mark = pass_mark;
    }
  }
  // Each kind's own keys; another kind's are mistakes.
  const std::string own = row.coefficients;
  for (const TaskKindRow& other : kTaskKindTable)
    if (other.coefficients != own && root.contains(other.coefficients)) {
      r.fail(other.coefficients, "only for kind " + quotedForMessage(other.coefficients));
      return;
    }
  if (row.pulp == PulpRule::MustOpen && root.contains("pulp_exposure_cap")) {
    r.fail("pulp_exposure_cap", "not for kind " + quotedForMessage(row.name) +
                                    ", which must open the pulp (access.unopened_cap caps one that does not)");
    return;
  }
  if (root.contains("cavity_class")) {
    if (t->kind != TaskKind::Cavity) {
      r.fail("cavity_class", "only for kind \"cavity\"");
      return;
    }
    std::vector<std::string> classes;
    for (int c = 1; c <= 6; ++c) classes.push_back(cavityClassName(c));
    size_t black = 0;
    if (!r.choice(root, "", "cavity_class", classes, &black)) return;
    t->cavity_class = int(black) + 1;
  }
  if (const json* access = r.member(root, "", "access", false)) {
    if (row.pulp != PulpRule::MustOpen) {
      r.fail("access", "only for kind " + quotedKinds([](const TaskKindRow& k) { return k.pulp == PulpRule::MustOpen; }));
      return;
    }
    readAccess(*access, r, t);
    if (r.failed()) return;
  }
  if (hasFailureTime(row)) {
    if (!r.number(root, "", "failure_s", true, 0, false, kHuge, "> 0 and <= 1e9", &t->failure_s)) return;
    if (!(t->failure_s > t->target_s)) {
      r.fail("failure_s", json(t->failure_s).dump() + " is not > target_s (" + json(t->target_s).dump() + ")");
      return;
    }
    if (const json* caries = r.member(root, "", own.c_str(), false)) readCaries(*caries, r, t);
    return;
  }
  if (root.contains("failure_s")) {
    r.fail("failure_s", "only for kind " + quotedKinds([](const TaskKindRow& k) { return hasFailureTime(k); }));
    return;
  }
  if (t->kind == TaskKind::Crown) {
    const json* crown = r.member(root, "", own.c_str(), false);
    readCrown(crown ? *crown : json::object(), r, t);
    return;
  }
  // Version 1 requires the cavity object (it holds the ideal); version 2 only its coefficients.
  if (const json* cavity = r.member(root, "", own.c_str(), version == 1)) readCavity(*cavity, version, r, t);
}

}  // namespace

const char* taskKindName(TaskKind kind) { return taskKindRow(kind).name; }

const char* cavityClassName(int cavity_class) {
  static const char* const kNames[] = {"I", "II", "III", "IV", "V", "VI"};
  return cavity_class >= 1 && cavity_class <= 6 ? kNames[cavity_class - 1] : "";
}

int cavityClassFromName(const std::string& name) {
  for (int c = 1; c <= 6; ++c)
    if (name == cavityClassName(c)) return c;
  return 0;
}

Result<Task> parseTask(const std::string& json_text, const std::string& where) {
  try {
    json root;
    std::string error;
    if (!parseStrictJson(json_text, &root, &error)) return makeError(where, error);
    Task task;
    TaskReader reader;
    readTask(root, reader, &task);
    if (reader.failed()) return makeError(where, reader.error());
    return task;
  } catch (const std::exception& e) {
    // Not reached for any input the tests know of; a task file must never take the caller down.
    return makeError(where, "cannot read task: " + jsonExceptionText(e));
  }
}

Result<Task> loadTask(const std::string& path) {
  auto bytes = readFileBytes(path, kMaxTaskBytes);
  if (!bytes) return bytes.error();
  return parseTask(std::string(bytes->begin(), bytes->end()), path);
}

}  // namespace dentsim
