// Reads and writes the score report's reader-facing keys (see score_summary.h for which and why).
#include "eval/score_summary.h"

#include <cmath>

#include "eval/tooth_diff.h"
#include "volume/brick_volume.h"

namespace dentsim {

namespace {

using ojson = nlohmann::ordered_json;

constexpr const char* kReportFormat = "dentsim-score";

// The value at `key` of an object; null when either is missing.
const ojson* member(const ojson& j, const char* key) {
  if (!j.is_object()) return nullptr;
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

// A finite number at `key`; none when missing or of another type (left out, not an error).
std::optional<double> numberAt(const ojson& j, const char* key) {
  const ojson* v = member(j, key);
  if (!v || !v->is_number() || !std::isfinite(v->get<double>())) return std::nullopt;
  return v->get<double>();
}

// A count at `key`: a whole number of at least 0; a negative or fractional one reads as its
// nearest count, since a reader only compares it with 0.
std::optional<uint64_t> countAt(const ojson& j, const char* key) {
  const ojson* v = member(j, key);
  if (!v || !v->is_number()) return std::nullopt;
  if (v->is_number_unsigned()) return v->get<uint64_t>();
  const double d = v->get<double>();
  if (!std::isfinite(d)) return std::nullopt;
  return d <= 0 ? uint64_t(0) : uint64_t(std::llround(d));
}

std::optional<bool> boolAt(const ojson& j, const char* key) {
  const ojson* v = member(j, key);
  if (!v || !v->is_boolean()) return std::nullopt;
  return v->get<bool>();
}

std::optional<std::string> textAt(const ojson& j, const char* key) {
  const ojson* v = member(j, key);
  if (!v || !v->is_string()) return std::nullopt;
  return v->get<std::string>();
}

// A string at `key` that may be missing or null, and is an error otherwise.
Result<std::optional<std::string>> optionalText(const ojson& report, const char* key) {
  const ojson* v = member(report, key);
  if (!v || v->is_null()) return std::optional<std::string>{};
  if (!v->is_string()) return Error{std::string(key) + ": not a string"};
  return std::optional<std::string>{v->get<std::string>()};
}

std::vector<ScoreReportPart> partsOf(const ojson& list, bool deduction) {
  std::vector<ScoreReportPart> parts;
  if (!list.is_object()) return parts;
  for (const auto& [name, j] : list.items()) {
    if (!j.is_object()) continue;
    ScoreReportPart p;
    p.name = name;
    p.deduction = deduction;
    const ojson* points = member(j, "points");
    p.has_points = points && (points->is_null() || numberAt(j, "points"));
    p.points = numberAt(j, "points");
    p.max = numberAt(j, "max");
    p.table_points = numberAt(j, "table_points");
    p.earned_share = numberAt(j, "earned_share");
    p.cap = numberAt(j, "cap");
    p.applied = boolAt(j, "applied");
    parts.push_back(std::move(p));
  }
  return parts;
}

ojson partJson(const ScoreReportPart& p) {
  ojson j = ojson::object();
  if (p.has_points) j["points"] = p.points ? ojson(*p.points) : ojson(nullptr);
  if (p.max) j["max"] = *p.max;
  if (p.table_points) j["table_points"] = *p.table_points;
  if (p.earned_share) j["earned_share"] = *p.earned_share;
  if (p.cap) j["cap"] = *p.cap;
  if (p.applied) j["applied"] = *p.applied;
  return j;
}

std::optional<ScoreReportSession> sessionOf(const ojson& j) {
  ScoreReportSession s;
  s.elapsed_s = numberAt(j, "elapsed_s");
  s.contact_samples = countAt(j, "contact_samples");
  s.force_over = countAt(j, "force_over");
  s.max_force_n = numberAt(j, "max_force_n");
  s.mean_force_n = numberAt(j, "mean_force_n");
  // A report scored without a session says why in its place ({"missing": ...}): no statistics.
  if (s == ScoreReportSession{}) return std::nullopt;
  return s;
}

// An agreement needs its band and its share within; the rest of the shares are optional.
std::optional<ScoreReportAgreement> agreementOf(const ojson& j) {
  const auto band = numberAt(j, "band_mm"), within = numberAt(j, "within_percent");
  if (!band || !within) return std::nullopt;
  ScoreReportAgreement a;
  a.band_mm = *band;
  a.samples = countAt(j, "samples");
  a.within_percent = *within;
  a.beyond_percent = numberAt(j, "beyond_percent");
  a.short_percent = numberAt(j, "short_percent");
  return a;
}

}  // namespace

ojson ScoreReportSummary::toJson() const {
  ojson j = ojson::object();
  j["format"] = kReportFormat;
  j["version"] = version;
  ojson task = ojson::object();
  task["name"] = task_name;
  if (!task_kind.empty()) task["kind"] = task_kind;
  if (!task_title.empty()) task["title"] = task_title;
  j["task"] = std::move(task);
  j["total"] = total;
  if (total_max) j["total_max"] = *total_max;
  if (paper_total) j["paper_total"] = *paper_total;
  ojson components = ojson::object(), deductions = ojson::object();
  for (const ScoreReportPart& p : parts) (p.deduction ? deductions : components)[p.name] = partJson(p);
  if (adjacent_removed_mm3) {
    ojson& adjacent = deductions["adjacent"];
    adjacent["removed_mm3"] = *adjacent_removed_mm3;
    adjacent["damaged"] = adjacent_damaged;
  }
  if (!components.empty()) j["components"] = std::move(components);
  if (completion_share) j["completion"] = {{"share", *completion_share}};
  if (!deductions.empty()) j["deductions"] = std::move(deductions);
  if (caries_remaining_mm3) j["caries_remaining_mm3"] = *caries_remaining_mm3;
  j["pulp_exposed"] = pulp_exposed;
  if (healthy_outside_zone_mm3) j["zones"] = {{"healthy_outside_zone_mm3", *healthy_outside_zone_mm3}};
  ojson volumes = ojson::object();
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (removed_mm3[t]) volumes[materialName(kScoredTissues[t])] = {{"removed_mm3", *removed_mm3[t]}};
  ojson all = ojson::object();
  if (undercut_mm3) all["undercut_mm3"] = *undercut_mm3;
  if (overcut_mm3) all["overcut_mm3"] = *overcut_mm3;
  if (!all.empty()) volumes["all"] = std::move(all);
  if (!volumes.empty()) j["volumes"] = std::move(volumes);
  if (session) {
    ojson s = ojson::object();
    if (session->elapsed_s) s["elapsed_s"] = *session->elapsed_s;
    if (session->contact_samples) s["contact_samples"] = *session->contact_samples;
    if (session->force_over) s["force_over"] = *session->force_over;
    if (session->max_force_n) s["max_force_n"] = *session->max_force_n;
    if (session->mean_force_n) s["mean_force_n"] = *session->mean_force_n;
    j["session"] = std::move(s);
  }
  if (agreement) {
    ojson a = ojson::object();
    a["band_mm"] = agreement->band_mm;
    if (agreement->samples) a["samples"] = *agreement->samples;
    a["within_percent"] = agreement->within_percent;
    if (agreement->beyond_percent) a["beyond_percent"] = *agreement->beyond_percent;
    if (agreement->short_percent) a["short_percent"] = *agreement->short_percent;
    j["surface_agreement"] = std::move(a);
  }
  if (guided) {
    ojson g = ojson::object();
    g["source"] = guided->source;
    if (guided->source_hash) g["source_hash"] = *guided->source_hash;
    if (guided->stiffness_n_per_mm) g["stiffness_n_per_mm"] = *guided->stiffness_n_per_mm;
    if (guided->max_force_n) g["max_force_n"] = *guided->max_force_n;
    j["guided"] = std::move(g);
  }
  if (statement_id) j["statement_id"] = *statement_id;
  if (student) j["student"] = *student;
  if (timestamp) j["timestamp"] = *timestamp;
  return j;
}

Result<ScoreReportSummary> ScoreReportSummary::fromJson(const ojson& report) {
  if (!report.is_object()) return Error{"not a JSON object"};
  if (textAt(report, "format") != kReportFormat) return Error{"format: missing or not \"dentsim-score\""};
  ScoreReportSummary s;
  if (const auto v = numberAt(report, "version")) s.version = int(*v);
  const ojson* task = member(report, "task");
  const auto name = task ? textAt(*task, "name") : std::nullopt;
  if (!name || name->empty()) return Error{"task.name: missing or not a string"};
  s.task_name = *name;
  s.task_title = textAt(*task, "title").value_or("");
  s.task_kind = textAt(*task, "kind").value_or("");
  const auto total = numberAt(report, "total");
  if (!total || *total < 0 || *total > 100) return Error{"total: missing or not a number in [0, 100]"};
  s.total = *total;
  s.total_max = numberAt(report, "total_max");
  s.paper_total = numberAt(report, "paper_total");

  if (const ojson* pulp = member(report, "pulp_exposed"); pulp && !pulp->is_null()) {
    if (!pulp->is_boolean()) return Error{"pulp_exposed: not true or false"};
    s.pulp_exposed = pulp->get<bool>();
  }
  if (const ojson* guide = member(report, "guided"); guide && !guide->is_null()) {
    if (!guide->is_object()) return Error{"guided: not an object"};
    s.guided = ScoreReportGuide{textAt(*guide, "source").value_or(""), textAt(*guide, "source_hash"),
                                numberAt(*guide, "stiffness_n_per_mm"), numberAt(*guide, "max_force_n")};
  }
  auto student = optionalText(report, "student");
  if (!student) return student.error();
  s.student = *student;
  auto stamp = optionalText(report, "timestamp");
  if (!stamp) return stamp.error();
  s.timestamp = *stamp;
  auto id = optionalText(report, "statement_id");
  if (!id) return id.error();
  s.statement_id = *id;

  const ojson none;
  const auto at = [&](const char* key) -> const ojson& {
    const ojson* v = member(report, key);
    return v ? *v : none;
  };
  s.parts = partsOf(at("components"), false);
  for (ScoreReportPart& p : partsOf(at("deductions"), true)) s.parts.push_back(std::move(p));
  s.completion_share = numberAt(at("completion"), "share");
  if (const ojson* adjacent = member(at("deductions"), "adjacent")) {
    s.adjacent_removed_mm3 = numberAt(*adjacent, "removed_mm3");
    s.adjacent_damaged = boolAt(*adjacent, "damaged").value_or(false);
  }
  const ojson& volumes = at("volumes");
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (const ojson* tissue = member(volumes, materialName(kScoredTissues[t]).c_str())) s.removed_mm3[t] = numberAt(*tissue, "removed_mm3");
  if (const ojson* all = member(volumes, "all")) {
    s.overcut_mm3 = numberAt(*all, "overcut_mm3");
    s.undercut_mm3 = numberAt(*all, "undercut_mm3");
  }
  s.healthy_outside_zone_mm3 = numberAt(at("zones"), "healthy_outside_zone_mm3");
  s.caries_remaining_mm3 = numberAt(report, "caries_remaining_mm3");
  s.session = sessionOf(at("session"));
  s.agreement = agreementOf(at("surface_agreement"));
  return s;
}

}  // namespace dentsim
