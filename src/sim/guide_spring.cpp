// GuideSpring: the guide's path from a professional's session, its header JSON, and the spring's step.
#include "sim/guide_spring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "io/file_hash.h"
#include "io/session_file.h"
#include "sim/tool_proxy.h"

namespace dentsim {

namespace {

using Json = nlohmann::ordered_json;

double roundTenthMicron(double v) { return std::round(v * 1e4) / 1e4; }

std::string hex16(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

GuidePath guidePathFrom(const ProPath& pro, const GuideSettings& settings, const std::string& source,
                        const std::string& source_hash) {
  GuidePath g;
  g.settings = settings;
  g.source = source;
  g.source_hash = source_hash;
  g.source_task = pro.task();
  g.source_tooth_hash = pro.toothHash();
  g.spacing_s = ProPath::kSampleEveryS;
  g.points.reserve(pro.poses().size());
  for (const ProPose& p : pro.poses()) {
    const Vec3& x = p.drill.position;
    g.points.push_back({roundTenthMicron(x.x), roundTenthMicron(x.y), roundTenthMicron(x.z)});
  }
  return g;
}

GuidePath guidePathFromScript(const PenPath& script, const GuideSettings& settings, const std::string& source,
                              const std::string& task, const std::string& tooth_hash) {
  GuidePath g;
  g.settings = settings;
  g.source = source;
  g.source_task = task;
  g.source_tooth_hash = tooth_hash;
  g.spacing_s = ProPath::kSampleEveryS;
  std::vector<const PenSample*> drill;
  for (const PenSample& s : script.samples)
    if (s.pen == PenRole::Drill) drill.push_back(&s);
  if (!drill.empty()) {
    size_t k = 0;
    const double end = drill.back()->t_s;
    for (size_t i = 0; double(i) * g.spacing_s <= end + 1e-12 && g.points.size() < kMaxGuidePoints; ++i) {
      const double t = double(i) * g.spacing_s;
      while (k + 1 < drill.size() && drill[k + 1]->t_s <= t) ++k;
      Vec3 x = drill[k]->pose.position;
      if (k + 1 < drill.size() && drill[k + 1]->t_s > drill[k]->t_s && t > drill[k]->t_s) {
        const double a = (t - drill[k]->t_s) / (drill[k + 1]->t_s - drill[k]->t_s);
        x = x + (drill[k + 1]->pose.position - x) * a;
      }
      g.points.push_back({roundTenthMicron(x.x), roundTenthMicron(x.y), roundTenthMicron(x.z)});
    }
  }
  g.source_hash = hex16(bytesHash(g.points.data(), g.points.size() * sizeof(Vec3)));
  return g;
}

Result<GuidePath> loadGuidePath(const std::string& path, const GuideSettings& settings) {
  auto session = readSessionFile(path);
  if (!session) return session.error();
  auto pro = ProPath::fromSession(*session, path);
  if (!pro) return pro.error();
  auto hash = fileHash(path);
  if (!hash) return hash.error();
  // Through its own JSON, so that the guide a run uses is the one its session's header holds.
  return parseGuideJson(guideJson(guidePathFrom(*pro, settings, path, hex16(*hash))), path);
}

std::string guideJson(const GuidePath& path) {
  Json points = Json::array();
  for (const Vec3& p : path.points) points.push_back(Json::array({p.x, p.y, p.z}));
  Json j = Json::object();
  j["source"] = path.source;
  j["source_hash"] = path.source_hash;
  j["source_task"] = path.source_task;
  j["source_tooth_hash"] = path.source_tooth_hash;
  j["stiffness_n_per_mm"] = path.settings.stiffness_n_per_mm;
  j["max_force_n"] = path.settings.max_force_n;
  j["lookahead_s"] = path.settings.lookahead_s;
  j["search_s"] = path.settings.search_s;
  j["spacing_s"] = path.spacing_s;
  j["start_index"] = path.start_index;
  j["points"] = std::move(points);
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Result<GuidePath> parseGuideJson(const std::string& text, const std::string& where) {
  const std::string w = where + ": guide";
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return makeError(w, "not a JSON object");
  GuidePath g;
  auto str = [&](const char* key, std::string* out) -> Status {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_string()) return makeError(w, std::string(key) + ": expected a string");
    *out = it->get<std::string>();
    return Ok{};
  };
  // Each number finite and in its range: `lo_open` excludes the lower bound.
  auto num = [&](const char* key, double lo, bool lo_open, double hi, double* out) -> Status {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_number()) return makeError(w, std::string(key) + ": expected a number");
    const double v = it->get<double>();
    if (!std::isfinite(v) || v < lo || (lo_open && v == lo) || v > hi)
      return makeError(w, std::string(key) + ": " + std::to_string(v) + " is out of range");
    *out = v;
    return Ok{};
  };
  for (Status st : {str("source", &g.source), str("source_hash", &g.source_hash), str("source_task", &g.source_task),
                    str("source_tooth_hash", &g.source_tooth_hash),
                    num("stiffness_n_per_mm", 0.0, true, 100.0, &g.settings.stiffness_n_per_mm),
                    num("max_force_n", 0.0, true, 100.0, &g.settings.max_force_n),
                    num("lookahead_s", 0.0, false, 60.0, &g.settings.lookahead_s),
                    num("search_s", 0.0, true, 3600.0, &g.settings.search_s),
                    num("spacing_s", 1e-4, false, 1.0, &g.spacing_s)})
    if (!st) return st.error();
  if (g.settings.search_s / g.spacing_s > double(kMaxGuideSearchPoints))
    return makeError(w, "search_s: " + std::to_string(g.settings.search_s) + " s would search more than " +
                            std::to_string(kMaxGuideSearchPoints) + " points a step");
  const auto start = j.find("start_index");
  if (start == j.end() || !start->is_number_unsigned()) return makeError(w, "start_index: expected a whole number >= 0");
  g.start_index = start->get<size_t>();
  const auto pts = j.find("points");
  if (pts == j.end() || !pts->is_array() || pts->empty())
    return makeError(w, "points: expected a non-empty array of [x, y, z]");
  if (pts->size() > kMaxGuidePoints)
    return makeError(w, "points: " + std::to_string(pts->size()) + " points; a guide follows at most " +
                            std::to_string(kMaxGuidePoints) + " (an hour of the professional's session)");
  g.points.reserve(pts->size());
  for (size_t i = 0; i < pts->size(); ++i) {
    const Json& p = (*pts)[i];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      return makeError(w, "points[" + std::to_string(i) + "]: expected [x, y, z]");
    const Vec3 v{p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    if (!finite(v)) return makeError(w, "points[" + std::to_string(i) + "]: not finite");
    g.points.push_back(v);
  }
  if (g.start_index >= g.points.size())
    return makeError(w, "start_index: " + std::to_string(g.start_index) + " is past the last of the " +
                            std::to_string(g.points.size()) + " points");
  return g;
}

Vec3 GuideSpring::force(const Vec3& bur_grip) {
  const std::vector<Vec3>& pts = path_.points;
  if (pts.empty()) return {};
  const GuideSettings& s = path_.settings;
  const auto window = size_t(std::llround(s.search_s / path_.spacing_s)) + 1;
  const size_t end = std::min(pts.size(), cursor_ + window);
  double best = INFINITY;
  for (size_t i = cursor_; i < end; ++i) {
    const Vec3 d = pts[i] - bur_grip;
    const double d2 = dot(d, d);
    if (d2 < best) {
      best = d2;
      cursor_ = i;
    }
  }
  const size_t ahead = std::min(pts.size() - 1, cursor_ + size_t(std::llround(s.lookahead_s / path_.spacing_s)));
  Vec3 f = (pts[ahead] - bur_grip) * s.stiffness_n_per_mm;
  clampLength(&f, s.max_force_n);
  return finite(f) ? f : Vec3{};
}

}  // namespace dentsim
