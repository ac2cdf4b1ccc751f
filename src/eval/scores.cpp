// The score formulas of Tables 4 and 5 as corrected and extended, the input checks, the JSON report and the terminal line.
//
// Contents
//   1. Caries removal
//   2. Cavity preparation
//   3. Warnings
//   4. The report
//   5. The terminal line
#include "eval/scores.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "eval/task_kinds.h"

namespace dentsim {

double clampScore(double v, double lo, double hi) { return std::min(hi, std::max(lo, v)); }

namespace {

// The part of a session's contact samples over the force limit [%]; 0 without contact samples.
double forceOverPercent(const SessionStats& s) {
  return s.contact_samples > 0 ? 100.0 * double(std::min(s.force_over, s.contact_samples)) / double(s.contact_samples)
                               : 0.0;
}

// The cap an exposed pulp puts on a total out of total_max: the task's cap is out of 100.
double pulpCap(const Task& task, double total_max) { return task.pulp_exposure_cap * total_max / 100.0; }
// The same for an access cavity whose pulp chamber was left closed.
double unopenedCap(const Task& task, double total_max) { return task.access.unopened_cap * total_max / 100.0; }

// Without a session, the parts that need one are not scored: the total is out of what remains.
constexpr double kSessionPoints = 50.0;

}  // namespace

// Every kind's deduction for an adjacent tooth cut (docs/SCORING.md section 3, "Adjacent teeth").
AdjacentScore scoreAdjacent(const ToothDiff& diff, const Task& task) {
  const TissueAmounts& n = diff.adjacent();
  const AdjacentTask& t = task.adjacent;
  AdjacentScore a;
  a.has_neighbour = n.initial > 0;
  a.initial_mm3 = diff.mm3(n.initial);
  a.removed_mm3 = diff.mm3(n.removed);
  a.noise_floor_mm3 = t.noise_voxels * diff.mm3(DS_FILL_FULL);
  // Compared in fill units, so that a test can count the floor in voxels exactly.
  a.damaged = double(n.removed) > t.noise_voxels * DS_FILL_FULL;
  // Any damage is a serious error, so it costs min_points however small; more costs more.
  if (a.damaged) a.deduction = t.min_points + t.coefficient * a.removed_mm3;
  return a;
}

// ---- 1. caries removal ---------------------------------------------------------------------------

CariesScore scoreCariesRemoval(const ToothDiff& diff, const SessionStats* stats, const Task& task) {
  CariesScore s;
  const TissueAmounts& caries = diff.tissue(Material::Caries);
  // Against a professional's cut, the caries to remove is what the professional removed: one who
  // leaves a layer over the pulp (selective removal) sets that as the standard, not all the lesion.
  const bool against_ideal = diff.has_ideal && caries.target > 0;
  s.against_ideal = against_ideal;
  s.removed_fraction = against_ideal ? double(caries.target_removed) / double(caries.target)
                       : caries.initial > 0 ? double(caries.removed) / double(caries.initial) : 0.0;
  s.removal = 50.0 * s.removed_fraction;
  if (stats) {
    // Time is credit for finishing the removal quickly, so an attempt that removed no caries earns
    // none; otherwise an empty attempt would score 25.
    s.time = caries.removed > 0
                 ? clampScore(25.0 * (task.failure_s - stats->elapsed_s) / (task.failure_s - task.target_s), 0.0, 25.0)
                 : 0.0;
    // No contact samples: the student never touched the tooth, and there is no force to credit.
    s.force = stats->contact_samples > 0
                  ? clampScore(25.0 * double(stats->contact_samples - std::min(stats->force_over, stats->contact_samples)) /
                                   double(stats->contact_samples),
                               0.0, 25.0)
                  : 0.0;
  }
  s.paper_total = s.removal + s.time.value_or(0.0) + s.force.value_or(0.0);
  // Time and force are credit for how the removal was done, so they are earned only for the share
  // of it that was: a token cut into the lesion would otherwise collect 50 for being quick and light.
  s.earned_time = s.removed_fraction * s.time.value_or(0.0);
  s.earned_force = s.removed_fraction * s.force.value_or(0.0);
  s.total_max = 50.0 + (stats ? kSessionPoints : 0.0);

  // Healthy tissue cut outside the allowed zone, as a share of the lesion: a larger lesion needs a
  // larger opening. A tooth without caries has nothing to scale by: any such cut costs everything.
  const uint64_t outside = diff.healthy().container_removed;
  s.healthy_outside_mm3 = diff.mm3(outside);
  if (caries.initial > 0) {
    s.healthy_outside_percent = 100.0 * double(outside) / double(caries.initial);
    s.healthy_deduction = task.caries.healthy_coefficient * s.healthy_outside_percent;
  } else if (outside > 0) {
    s.healthy_deduction = s.total_max;
  }
  s.adjacent = scoreAdjacent(diff, task);
  s.total = clampScore(s.removal + s.earned_time + s.earned_force - s.healthy_deduction - s.adjacent.deduction, 0.0,
                       s.total_max);
  s.pulp_exposed = diff.pulp_exposed;
  s.exposed_pulp_voxels = diff.exposed_pulp_voxels;
  if (s.pulp_exposed && s.total > pulpCap(task, s.total_max)) {
    s.total = pulpCap(task, s.total_max);
    s.pulp_cap_applied = true;
  }

  s.caries_initial_mm3 = diff.mm3(caries.initial);
  s.caries_removed_mm3 = diff.mm3(caries.removed);
  s.caries_remaining_mm3 = diff.mm3(caries.remaining);
  for (size_t t = 0; t < kTissueCount; ++t) s.removed_mm3[t] = diff.mm3(diff.tissue(kTissueTable[t].material).removed);
  return s;
}

// ---- 2. cavity preparation -----------------------------------------------------------------------

Result<CavityScore> scoreCavityPreparation(const ToothDiff& diff, const SessionStats* stats, const Task& task) {
  if (!diff.has_ideal) return makeError("", "cavity preparation needs the ideal (the professional's final tooth)");
  const TissueAmounts all = diff.total();
  if (all.target == 0) return makeError("", "the ideal cavity is empty: the ideal tooth removed nothing from the initial one");
  const CavityTask& c = task.cavity;
  CavityScore s;
  const double ideal = double(all.target);
  // Fill units stand for volume, so the ratio of units is the ratio of volumes.
  s.undercut_percent = double(all.undercut()) * 100.0 / ideal;
  s.overcut_percent = double(all.overcut()) * 100.0 / ideal;
  s.nothing_removed = all.removed == 0;
  s.ideal_missed = all.target_removed == 0;
  s.completion = double(all.target_removed) / ideal;
  s.undercut = clampScore(25.0 - double(all.undercut()) * c.undercut_coefficient * 100.0 / ideal, 0.0, 25.0);
  // Table 5 counts every voxel cut beyond the ideal; the total forgives what lies in the leeway by
  // near_overcut_weight (the paper's own over-cut part stays in paper_total).
  const double paper_overcut = clampScore(25.0 - double(all.overcut()) * c.overcut_coefficient * 100.0 / ideal, 0.0, 25.0);
  const double counted = double(all.container_removed) + c.near_overcut_weight * double(all.leeway_removed);
  s.overcut_counted_mm3 = diff.mm3(1) * counted;
  s.overcut = clampScore(25.0 - counted * c.overcut_coefficient * 100.0 / ideal, 0.0, 25.0);
  if (stats) {
    s.parallel = clampScore(25.0 - double(stats->parallel_over) * c.parallel_coefficient, 0.0, 25.0);
    s.time = clampScore(25.0 - std::max(0.0, stats->elapsed_s - task.target_s) * c.time_coefficient / 60.0, 0.0, 25.0);
    s.force_deduction = c.force_coefficient * forceOverPercent(*stats);
  }
  // Table 5's parts are independent: an attempt that did a third of the work keeps the whole
  // over-cut, parallel and time parts for the two thirds it never cut, and passed at 75. Those three
  // measure how the preparation was cut, so they are earned only for the share of it that was: a
  // third done earns a third of them. The under-cut part already measures the share missing, and the
  // force errors are a deduction, charged in full whatever was cut (docs/SCORING.md section 5).
  s.earned_overcut = s.completion * s.overcut;
  if (s.parallel) s.earned_parallel = s.completion * *s.parallel;
  if (s.time) s.earned_time = s.completion * *s.time;
  s.paper_total = s.undercut + paper_overcut + s.parallel.value_or(0.0) + s.time.value_or(0.0);
  s.total_max = 50.0 + (stats ? kSessionPoints : 0.0);
  s.adjacent = scoreAdjacent(diff, task);
  s.total = clampScore(s.undercut + s.earned_overcut + s.earned_parallel.value_or(0.0) + s.earned_time.value_or(0.0) -
                           s.force_deduction.value_or(0.0) - s.adjacent.deduction,
                       0.0, s.total_max);
  s.pulp_exposed = diff.pulp_exposed;
  s.exposed_pulp_voxels = diff.exposed_pulp_voxels;
  // Which cap applies is the kind's pulp rule (eval/task_kinds.h), not its name.
  s.access = taskKindRow(task.kind).pulp == PulpRule::MustOpen;
  if (s.access) {
    // The access exists to reach the canals: without the chamber open it has failed, however close
    // its outline came; opened, the pulp is where the exercise ends, not a fault.
    if (!s.pulp_exposed && s.total > unopenedCap(task, s.total_max)) {
      s.total = unopenedCap(task, s.total_max);
      s.unopened_cap_applied = true;
    }
  } else if (s.pulp_exposed && s.total > pulpCap(task, s.total_max)) {
    s.total = pulpCap(task, s.total_max);
    s.pulp_cap_applied = true;
  }
  s.ideal_mm3 = diff.mm3(all.target);
  s.removed_mm3 = diff.mm3(all.removed);
  s.undercut_mm3 = diff.mm3(all.undercut());
  s.overcut_mm3 = diff.mm3(all.overcut());
  s.overcut_near_mm3 = diff.mm3(all.leeway_removed);
  s.overcut_gross_mm3 = diff.mm3(all.container_removed);
  return s;
}

// ---- 3. warnings ---------------------------------------------------------------------------------

namespace {

std::string vecText(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", v.x, v.y, v.z);
  return text;
}

std::string crownText(const CrownEstimate& crown) {
  return crown.from_enamel ? "crown axis " + vecText(crown.axis) + ", estimated from the enamel"
                           : "crown assumed +z: the tooth has no enamel to tell";
}

}  // namespace

std::vector<std::string> scoreWarnings(const Task& task, const ToothDiff& diff, const std::string& tooth_name) {
  std::vector<std::string> out;
  const std::string who = "task " + task.name + " on " + tooth_name + ": ";
  char text[160];
  // More than 90 degrees from the crown: the bur would come in from the roots' side.
  const double angle = std::atan2(norm(cross(task.insertion_axis, diff.crown.axis)), dot(task.insertion_axis, diff.crown.axis)) *
                       (180.0 / std::numbers::pi);
  if (angle > 90.0) {
    std::snprintf(text, sizeof text, "%.0f degrees", angle);
    out.push_back(who + "the insertion axis " + vecText(task.insertion_axis) + " points away from the crown (" + text +
                  " from it; " + crownText(diff.crown) + ")");
  }
  const TissueAmounts all = diff.total();
  if (diff.has_ideal && all.target > 0 && 2 * diff.target_in_crown_half < all.target) {
    std::snprintf(text, sizeof text, "%.0f%%", 100.0 * double(all.target - diff.target_in_crown_half) / double(all.target));
    out.push_back(who + "the ideal cavity lies mostly outside the crown half of the tooth (" + text + " of it; " +
                  crownText(diff.crown) + "): is the ideal made for this tooth and its orientation?");
  }
  if (diff.has_ideal && all.removed > 0 && all.target > 0 && all.target_removed == 0)
    out.push_back(who + "the cut does not overlap the ideal cavity at all: it was made somewhere else");
  return out;
}

// ---- 4. the report -------------------------------------------------------------------------------

namespace {

using ojson = nlohmann::ordered_json;

constexpr const char* kReportFormat = "dentsim-score";
constexpr int kReportVersion = 2;

const char* idealKindName(IdealKind k) {
  switch (k) {
    case IdealKind::BuiltinPath: return "builtin_path";
    case IdealKind::Volume: return "volume";
    case IdealKind::Session: return "session";
  }
  return "unknown";
}

ojson header(const Task& task, const ScoreInputs& inputs) {
  ojson j = ojson::object();
  j["format"] = kReportFormat;
  j["version"] = kReportVersion;
  j["task"] = {{"name", task.name}, {"kind", taskKindName(task.kind)}, {"title", task.title}};
  ojson in = ojson::object();
  auto file = [](const std::string& s) { return s.empty() ? ojson(nullptr) : ojson(s); };
  in["task"] = file(inputs.task);
  in["initial"] = file(inputs.initial);
  in["final"] = file(inputs.final_);
  in["ideal"] = inputs.ideal ? ojson{{"kind", idealKindName(inputs.ideal->kind)}, {"path", inputs.ideal->path}, {"from", inputs.ideal_from}}
                             : ojson(nullptr);
  in["session"] = file(inputs.session);
  j["inputs"] = std::move(in);
  return j;
}

// A part: its points, or null with the reason it was not scored.
ojson part(const std::optional<double>& points, double max, const std::string& why_not) {
  ojson j = ojson::object();
  j["points"] = points ? ojson(*points) : ojson(nullptr);
  j["max"] = max;
  if (!points) j["not_scored"] = why_not;
  return j;
}

// A part earned in proportion to the work done: the points that count, and the table's own value.
ojson earnedPart(const std::optional<double>& earned, const std::optional<double>& table, double share, double max,
                 const std::string& why_not) {
  ojson j = part(earned, max, why_not);
  j["table_points"] = table ? ojson(*table) : ojson(nullptr);
  j["earned_share"] = share;
  return j;
}

// The headline and what it is out of; the parts not scored with their reason.
void totals(ojson& j, double total, double total_max, double paper_total, const std::vector<std::string>& not_scored,
            const ScoreInputs& inputs) {
  j["total"] = total;
  j["total_max"] = total_max;
  j["percent"] = total_max > 0 ? 100.0 * total / total_max : 0.0;
  j["paper_total"] = paper_total;
  ojson missing = ojson::array();
  for (const std::string& name : not_scored) missing.push_back({{"part", name}, {"reason", inputs.no_session_reason}});
  j["not_scored"] = std::move(missing);
}

ojson amountsJson(const ToothDiff& diff, const TissueAmounts& a) {
  ojson t = ojson::object();
  t["initial_mm3"] = diff.mm3(a.initial);
  t["remaining_mm3"] = diff.mm3(a.remaining);
  t["removed_mm3"] = diff.mm3(a.removed);
  t["target_mm3"] = diff.mm3(a.target);
  t["target_removed_mm3"] = diff.mm3(a.target_removed);
  t["leeway_mm3"] = diff.mm3(a.leeway);
  t["leeway_removed_mm3"] = diff.mm3(a.leeway_removed);
  t["container_mm3"] = diff.mm3(a.container);
  t["container_removed_mm3"] = diff.mm3(a.container_removed);
  if (diff.has_ideal) {
    t["ideal_cavity_mm3"] = diff.mm3(a.target);
    t["undercut_mm3"] = diff.mm3(a.undercut());
    t["overcut_mm3"] = diff.mm3(a.overcut());
    t["overcut_near_mm3"] = diff.mm3(a.leeway_removed);
    t["overcut_gross_mm3"] = diff.mm3(a.container_removed);
  }
  // The same sums in fill units, so that a reader can check them exactly.
  t["units"] = {{"initial", a.initial},   {"remaining", a.remaining},           {"removed", a.removed},
                {"target", a.target},     {"target_removed", a.target_removed}, {"leeway", a.leeway},
                {"leeway_removed", a.leeway_removed}, {"container", a.container},
                {"container_removed", a.container_removed}};
  return t;
}

ojson volumesJson(const ToothDiff& diff) {
  ojson j = ojson::object();
  j["voxel_mm"] = diff.voxel_mm;
  j["fill_unit_mm3"] = diff.mm3(1);
  // A tooth without a neighbour keeps the report it always had: no "neighbour" entry.
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (isToothTissue(kScoredTissues[t]) || diff.tissues[t].initial > 0)
      j[materialName(kScoredTissues[t])] = amountsJson(diff, diff.tissues[t]);
  j["healthy"] = amountsJson(diff, diff.healthy());
  j["all"] = amountsJson(diff, diff.total());
  j["pulp_exposed"] = diff.pulp_exposed;
  j["exposed_pulp_voxels"] = diff.exposed_pulp_voxels;
  return j;
}

// The three zones as Simodont reports them: the share of each that was removed [%].
ojson zonesJson(const ToothDiff& diff) {
  const TissueAmounts all = diff.total();
  auto percent = [](uint64_t part, uint64_t whole) { return whole > 0 ? ojson(100.0 * double(part) / double(whole)) : ojson(nullptr); };
  ojson j = ojson::object();
  j["target"] = diff.target_kind == TargetKind::IdealCavity ? "ideal cavity" : "caries and its access along the insertion axis";
  if (diff.target_kind == TargetKind::CariesAccess)
    j["insertion_axis"] = {diff.access_axis.x, diff.access_axis.y, diff.access_axis.z};
  j["leeway_mm"] = diff.leeway_mm;
  j["target_removed_percent"] = percent(all.target_removed, all.target);
  j["leeway_removed_percent"] = percent(all.leeway_removed, all.leeway);
  j["container_removed_percent"] = percent(all.container_removed, all.container);
  j["healthy_outside_zone_mm3"] = diff.mm3(diff.healthy().container_removed);
  j["crown"] = {{"axis", {diff.crown.axis.x, diff.crown.axis.y, diff.crown.axis.z}},
                {"from_enamel", diff.crown.from_enamel},
                {"target_in_crown_half_percent", percent(diff.target_in_crown_half, all.target)}};
  return j;
}

ojson sessionJson(const SessionStats* s, const ScoreInputs& inputs) {
  if (!s) return {{"missing", inputs.no_session_reason}};
  ojson j = ojson::object();
  j["rate_hz"] = s->rate_hz;
  j["steps"] = s->steps;
  j["lost_steps"] = s->lost_steps;
  j["elapsed_s"] = s->elapsed_s;
  j["contact_samples"] = s->contact_samples;
  j["force_over"] = s->force_over;
  j["parallel_over"] = s->parallel_over;
  j["max_force_n"] = s->max_force_n;
  j["mean_force_n"] = s->mean_force_n;
  j["max_tilt_deg"] = s->max_tilt_deg;
  return j;
}

// The adjacent-tooth deduction; the report holds it only when the initial tooth has a neighbour.
ojson adjacentJson(const Task& task, const AdjacentScore& a) {
  return {{"points", a.deduction},
          {"formula", "removed_mm3 > noise_floor_mm3 ? min_points + coefficient * removed_mm3 : 0"},
          {"removed_mm3", a.removed_mm3},
          {"initial_mm3", a.initial_mm3},
          {"noise_floor_mm3", a.noise_floor_mm3},
          {"noise_voxels", task.adjacent.noise_voxels},
          {"damaged", a.damaged},
          {"min_points", task.adjacent.min_points},
          {"coefficient", task.adjacent.coefficient}};
}

ojson pulpCapJson(const Task& task, bool exposed, bool applied, double total_max) {
  return {{"pulp_exposed", exposed}, {"cap", pulpCap(task, total_max)}, {"cap_of_100", task.pulp_exposure_cap}, {"applied", applied}};
}

ojson tail(ojson j, const ToothDiff& diff, const SessionStats* stats, const ScoreInputs& inputs) {
  j["zones"] = zonesJson(diff);
  j["warnings"] = inputs.warnings;
  j["volumes"] = volumesJson(diff);
  j["session"] = sessionJson(stats, inputs);
  return j;
}

}  // namespace

ojson scoreReportHeader(const Task& task, const ScoreInputs& inputs) { return header(task, inputs); }
void scoreReportTotals(ojson& report, double total, double total_max, double paper_total,
                       const std::vector<std::string>& not_scored, const ScoreInputs& inputs) {
  totals(report, total, total_max, paper_total, not_scored, inputs);
}
ojson adjacentDeductionJson(const Task& task, const AdjacentScore& adjacent) { return adjacentJson(task, adjacent); }
double pulpExposureCap(const Task& task, double total_max) { return pulpCap(task, total_max); }
ojson pulpExposureCapJson(const Task& task, bool exposed, bool applied, double total_max) {
  return pulpCapJson(task, exposed, applied, total_max);
}
ojson scoreZonesJson(const ToothDiff& diff) { return zonesJson(diff); }
ojson scoreVolumesJson(const ToothDiff& diff) { return volumesJson(diff); }
ojson scoreSessionJson(const SessionStats* stats, const ScoreInputs& inputs) { return sessionJson(stats, inputs); }

namespace {
ScoreLine scorePart(const char* name, std::optional<double> points, double max) { return {name, points, max, false, {}}; }
ScoreLine scoreDeduction(const char* name, std::optional<double> points) { return {name, points, 0.0, true, {}}; }
}  // namespace

// In the order scoreReportJson writes "components", then "deductions". (Filled one by one: an
// initializer list of these aggregates is destroyed twice by this compiler's optimizer.)
std::vector<ScoreLine> scoreLines(const CariesScore& s) {
  std::vector<ScoreLine> lines;
  lines.push_back(scorePart("removal", s.removal, 50.0));
  lines.push_back(scorePart("time", s.time ? std::optional<double>(s.earned_time) : std::nullopt, 25.0));
  lines.push_back(scorePart("force", s.force ? std::optional<double>(s.earned_force) : std::nullopt, 25.0));
  lines.push_back(scoreDeduction("healthy", s.healthy_deduction));
  if (s.adjacent.has_neighbour) lines.push_back(scoreDeduction("adjacent", s.adjacent.deduction));
  return lines;
}

std::vector<ScoreLine> scoreLines(const CavityScore& s) {
  std::vector<ScoreLine> lines;
  lines.push_back(scorePart("undercut", s.undercut, 25.0));
  lines.push_back(scorePart("overcut", s.earned_overcut, 25.0));
  lines.push_back(scorePart("parallel", s.earned_parallel, 25.0));
  lines.push_back(scorePart("time", s.earned_time, 25.0));
  lines.push_back(scoreDeduction("force", s.force_deduction));
  if (s.adjacent.has_neighbour) lines.push_back(scoreDeduction("adjacent", s.adjacent.deduction));
  return lines;
}

ojson scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff, const SessionStats* stats,
                      const CariesScore& s) {
  ojson j = header(task, inputs);
  const TissueAmounts& caries = diff.tissue(Material::Caries);
  std::vector<std::string> not_scored;
  if (!s.time) not_scored.push_back("time");
  if (!s.force) not_scored.push_back("force");
  totals(j, s.total, s.total_max, s.paper_total, not_scored, inputs);
  ojson c = ojson::object();
  c["removal"] = part(s.removal, 50, "");
  c["removal"]["formula"] = s.against_ideal ? "50 * caries_removed_of_the_ideal / caries_the_ideal_removed"
                                             : "50 * caries_removed / caries_initial";
  c["removal"]["against_ideal"] = s.against_ideal;
  c["removal"]["caries_removed_mm3"] = s.caries_removed_mm3;
  c["removal"]["caries_initial_mm3"] = s.caries_initial_mm3;
  c["removal"]["removed_fraction"] = s.removed_fraction;
  const auto earnedOf = [&](const std::optional<double>& p, double earned) { return p ? std::optional<double>(earned) : std::nullopt; };
  c["time"] = earnedPart(earnedOf(s.time, s.earned_time), s.time, s.removed_fraction, 25, inputs.no_session_reason);
  c["time"]["formula"] = "removed_fraction * 25 * (failure_s - elapsed_s) / (failure_s - target_s), the table's part in [0, 25]";
  c["time"]["elapsed_s"] = stats ? ojson(stats->elapsed_s) : ojson(nullptr);
  c["time"]["target_s"] = task.target_s;
  c["time"]["failure_s"] = task.failure_s;
  c["time"]["caries_removed"] = caries.removed > 0;
  c["force"] = earnedPart(earnedOf(s.force, s.earned_force), s.force, s.removed_fraction, 25, inputs.no_session_reason);
  c["force"]["formula"] = "removed_fraction * 25 * (contact_samples - force_over) / contact_samples, the table's part in [0, 25]; 0 without contact";
  c["force"]["contact_samples"] = stats ? ojson(stats->contact_samples) : ojson(nullptr);
  c["force"]["force_over"] = stats ? ojson(stats->force_over) : ojson(nullptr);
  c["force"]["force_error_n"] = task.force_error_n;
  j["components"] = std::move(c);
  j["completion"] = {{"share", s.removed_fraction},
                     {"rule", "time and force are earned in proportion to the share of the caries removed"}};
  ojson d = ojson::object();
  d["healthy"] = {{"points", s.healthy_deduction},
                  {"formula", "healthy_coefficient * 100 * healthy_outside_zone / caries_initial"},
                  {"healthy_outside_zone_mm3", s.healthy_outside_mm3},
                  {"percent_of_caries", s.healthy_outside_percent},
                  {"caries_initial_mm3", s.caries_initial_mm3},
                  {"coefficient", task.caries.healthy_coefficient}};
  if (s.adjacent.has_neighbour) d["adjacent"] = adjacentJson(task, s.adjacent);
  d["pulp_exposure"] = pulpCapJson(task, s.pulp_exposed, s.pulp_cap_applied, s.total_max);
  j["deductions"] = std::move(d);
  ojson healthy = ojson::object();
  for (size_t t = 0; t < kTissueCount; ++t)
    if (isHealthyTissue(kTissueTable[t].material)) healthy[kTissueTable[t].name] = s.removed_mm3[t];
  j["healthy_removed_mm3"] = std::move(healthy);
  j["caries_remaining_mm3"] = s.caries_remaining_mm3;
  j["pulp_exposed"] = s.pulp_exposed;
  return tail(std::move(j), diff, stats, inputs);
}

ojson scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff, const SessionStats* stats,
                      const CavityScore& s) {
  ojson j = header(task, inputs);
  const CavityTask& t = task.cavity;
  std::vector<std::string> not_scored;
  if (!s.parallel) not_scored.push_back("parallel");
  if (!s.time) not_scored.push_back("time");
  if (!s.force_deduction) not_scored.push_back("force");
  totals(j, s.total, s.total_max, s.paper_total, not_scored, inputs);
  ojson c = ojson::object();
  c["undercut"] = part(s.undercut, 25, "");
  c["undercut"].update(ojson{{"formula", "25 - undercut * coefficient * 100 / ideal, in [0, 25]"},
                             {"undercut_mm3", s.undercut_mm3},
                             {"ideal_mm3", s.ideal_mm3},
                             {"percent_of_ideal", s.undercut_percent},
                             {"coefficient", t.undercut_coefficient}});
  c["overcut"] = earnedPart(s.earned_overcut, s.overcut, s.completion, 25, "");
  c["overcut"].update(ojson{{"formula", "completion * (25 - (overcut_gross + near_weight * overcut_near) * coefficient * 100 / ideal), the part in [0, 25]"},
                            {"near_weight", t.near_overcut_weight},
                            {"overcut_counted_mm3", s.overcut_counted_mm3},
                            {"overcut_mm3", s.overcut_mm3},
                            {"overcut_near_mm3", s.overcut_near_mm3},
                            {"overcut_gross_mm3", s.overcut_gross_mm3},
                            {"leeway_mm", diff.leeway_mm},
                            {"ideal_mm3", s.ideal_mm3},
                            {"percent_of_ideal", s.overcut_percent},
                            {"coefficient", t.overcut_coefficient}});
  c["parallel"] = earnedPart(s.earned_parallel, s.parallel, s.completion, 25, inputs.no_session_reason);
  c["parallel"].update(ojson{{"formula", "completion * (25 - parallel_over * coefficient), the table's part in [0, 25]"},
                             {"parallel_over", stats ? ojson(stats->parallel_over) : ojson(nullptr)},
                             {"contact_samples", stats ? ojson(stats->contact_samples) : ojson(nullptr)},
                             {"parallel_error_deg", t.parallel_error_deg},
                             {"insertion_axis", {task.insertion_axis.x, task.insertion_axis.y, task.insertion_axis.z}},
                             {"coefficient", t.parallel_coefficient}});
  c["time"] = earnedPart(s.earned_time, s.time, s.completion, 25, inputs.no_session_reason);
  c["time"].update(ojson{{"formula", "completion * (25 - max(0, elapsed_s - target_s) * coefficient / 60), the table's part in [0, 25]"},
                         {"elapsed_s", stats ? ojson(stats->elapsed_s) : ojson(nullptr)},
                         {"target_s", task.target_s},
                         {"coefficient", t.time_coefficient}});
  j["components"] = std::move(c);
  j["completion"] = {{"share", s.completion},
                     {"rule", "over-cut, parallel and time are earned in proportion to the share of the ideal cavity cut"},
                     {"ideal_removed_mm3", s.ideal_mm3 - s.undercut_mm3},
                     {"ideal_mm3", s.ideal_mm3}};
  ojson d = ojson::object();
  d["force"] = {{"points", s.force_deduction ? ojson(*s.force_deduction) : ojson(nullptr)},
                {"formula", "force_coefficient * 100 * force_over / contact_samples"},
                {"contact_samples", stats ? ojson(stats->contact_samples) : ojson(nullptr)},
                {"force_over", stats ? ojson(stats->force_over) : ojson(nullptr)},
                {"force_error_n", task.force_error_n},
                {"coefficient", t.force_coefficient}};
  if (!s.force_deduction) d["force"]["not_scored"] = inputs.no_session_reason;
  if (s.adjacent.has_neighbour) d["adjacent"] = adjacentJson(task, s.adjacent);
  if (s.access)
    d["pulp_unopened"] = {{"pulp_opened", s.pulp_exposed},
                          {"cap", unopenedCap(task, s.total_max)},
                          {"cap_of_100", task.access.unopened_cap},
                          {"applied", s.unopened_cap_applied}};
  else
    d["pulp_exposure"] = pulpCapJson(task, s.pulp_exposed, s.pulp_cap_applied, s.total_max);
  j["deductions"] = std::move(d);
  j["nothing_removed"] = s.nothing_removed;
  j["ideal_missed"] = s.ideal_missed;
  j["removed_mm3"] = s.removed_mm3;
  j["pulp_exposed"] = s.pulp_exposed;
  return tail(std::move(j), diff, stats, inputs);
}

// ---- 5. the terminal line ------------------------------------------------------------------------

namespace {

std::string fixed(double v, int digits = 2) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

// ", time 25.00 / 25" or nothing when the part was not scored.
std::string partText(const char* name, const std::optional<double>& points, int max) {
  return points ? std::string(", ") + name + " " + fixed(*points) + " / " + std::to_string(max) : "";
}

// ", adjacent tooth damaged -26.50" when the cut damaged a neighbour; nothing otherwise.
std::string adjacentText(const AdjacentScore& a) {
  return a.damaged ? ", adjacent tooth damaged -" + fixed(a.deduction) : "";
}

// "; adjacent tooth 0.015 mm^3 removed" on a tooth with a neighbour; nothing without one.
std::string adjacentVolumeText(const AdjacentScore& a) {
  if (!a.has_neighbour) return "";
  return "; adjacent tooth " + fixed(a.removed_mm3, 3) + " mm^3 removed" +
         (a.damaged ? "" : a.removed_mm3 > 0 ? " (within the noise floor)" : "");
}

std::string notScoredText(const std::vector<const char*>& parts, const ScoreInputs& inputs) {
  if (parts.empty()) return "";
  std::string list;
  for (size_t i = 0; i < parts.size(); ++i) list += (i == 0 ? "" : (i + 1 == parts.size() ? " and " : ", ")) + std::string(parts[i]);
  return "; " + list + " not scored: " + inputs.no_session_reason;
}

}  // namespace

std::string scoreSummary(const CariesScore& s, const ScoreInputs& inputs) {
  std::vector<const char*> missing;
  if (!s.time) missing.push_back("time");
  if (!s.force) missing.push_back("force");
  const auto earned = [](const std::optional<double>& p, double e) { return p ? std::optional<double>(e) : std::nullopt; };
  std::string line = "caries removal score " + fixed(s.total) + " / " + fixed(s.total_max, 0) + " (removal " +
                     fixed(s.removal) + " / 50" + partText("time", earned(s.time, s.earned_time), 25) +
                     partText("force", earned(s.force, s.earned_force), 25) +
                     (s.healthy_deduction > 0 ? ", healthy tissue -" + fixed(s.healthy_deduction) : ", no healthy tissue outside the zone") +
                     adjacentText(s.adjacent) + (s.pulp_cap_applied ? ", capped: pulp exposed" : "") +
                     notScoredText(missing, inputs) + "; time and force earned at the share removed; Table 4 alone " +
                     fixed(s.paper_total) + "): ";
  // Summed in table order, the order the report has always added them in, so the total keeps its bits.
  double healthy_mm3 = 0.0;
  std::string by_tissue;
  for (size_t t = 0; t < kTissueCount; ++t) {
    if (!isHealthyTissue(kTissueTable[t].material)) continue;
    healthy_mm3 += s.removed_mm3[t];
    by_tissue += (by_tissue.empty() ? "" : ", ") + std::string(kTissueTable[t].name) + " " + fixed(s.removed_mm3[t], 3);
  }
  line += fixed(100.0 * s.removed_fraction, 1) + "% of " + fixed(s.caries_initial_mm3, 3) + " mm^3 caries removed; healthy " +
          fixed(healthy_mm3, 3) + " mm^3 removed (" + by_tissue + "), " + fixed(s.healthy_outside_mm3, 3) +
          " mm^3 of it outside the allowed zone; pulp " + (s.pulp_exposed ? "exposed" : "not exposed") +
          adjacentVolumeText(s.adjacent);
  return line;
}

std::string scoreSummary(const CavityScore& s, const ScoreInputs& inputs) {
  std::vector<const char*> missing;
  if (!s.parallel) missing.push_back("parallel");
  if (!s.time) missing.push_back("time");
  if (!s.force_deduction) missing.push_back("force");
  std::string line = std::string(s.access ? "access cavity score " : "cavity preparation score ") + fixed(s.total) + " / " + fixed(s.total_max, 0) + " (under-cut " +
                     fixed(s.undercut) + " / 25, over-cut " + fixed(s.earned_overcut) + " / 25" +
                     partText("parallel", s.earned_parallel, 25) + partText("time", s.earned_time, 25) +
                     (!s.force_deduction ? "" : *s.force_deduction > 0 ? ", force errors -" + fixed(*s.force_deduction) : ", no force errors") +
                     adjacentText(s.adjacent) + (s.pulp_cap_applied ? ", capped: pulp exposed" : "") +
                     (s.unopened_cap_applied ? ", capped: pulp chamber not opened" : "") + (s.ideal_missed ? ", the ideal missed" : "") +
                     notScoredText(missing, inputs) + "; " + fixed(100.0 * s.completion, 1) +
                     "% of the ideal cut, so over-cut, parallel and time earned at that share; Table 5 alone " +
                     fixed(s.paper_total) + "): ";
  line += "ideal " + fixed(s.ideal_mm3, 3) + " mm^3, under-cut " + fixed(s.undercut_mm3, 3) + " mm^3, over-cut " +
          fixed(s.overcut_mm3, 3) + " mm^3 (" + fixed(s.overcut_near_mm3, 3) + " near, " + fixed(s.overcut_gross_mm3, 3) +
          " gross); " + (s.access ? (s.pulp_exposed ? "pulp chamber opened" : "pulp chamber not opened")
                                  : (s.pulp_exposed ? "pulp exposed" : "pulp not exposed")) +
          adjacentVolumeText(s.adjacent);
  return line;
}

}  // namespace dentsim
