// The score formulas of Tables 4 and 5 as corrected, and the JSON report that shows each with its inputs.
//
// Contents
//   1. Caries removal
//   2. Cavity preparation
//   3. The report
#include "eval/scores.h"

#include <algorithm>

namespace dentsim {

double clampScore(double v, double lo, double hi) { return std::min(hi, std::max(lo, v)); }

// ---- 1. caries removal ---------------------------------------------------------------------------

CariesScore scoreCariesRemoval(const ToothDiff& diff, const SessionStats& stats, const Task& task) {
  CariesScore s;
  const TissueAmounts& caries = diff.tissue(Material::Caries);
  s.removed_fraction = caries.initial > 0 ? double(caries.removed) / double(caries.initial) : 0.0;
  s.removal = 50.0 * s.removed_fraction;
  // Time is credit for finishing the removal quickly, so an attempt that removed no caries earns none;
  // otherwise an empty attempt would score 25.
  if (caries.removed > 0)
    s.time = clampScore(25.0 * (task.failure_s - stats.elapsed_s) / (task.failure_s - task.target_s), 0.0, 25.0);
  // No contact samples: the student never touched the tooth, and there is no force to credit.
  if (stats.contact_samples > 0)
    s.force = clampScore(25.0 * double(stats.contact_samples - std::min(stats.force_over, stats.contact_samples)) /
                             double(stats.contact_samples),
                         0.0, 25.0);
  s.total = s.removal + s.time + s.force;
  s.caries_initial_mm3 = diff.mm3(caries.initial);
  s.caries_removed_mm3 = diff.mm3(caries.removed);
  s.caries_remaining_mm3 = diff.mm3(caries.remaining);
  s.enamel_removed_mm3 = diff.mm3(diff.tissue(Material::Enamel).removed);
  s.dentin_removed_mm3 = diff.mm3(diff.tissue(Material::Dentin).removed);
  s.pulp_removed_mm3 = diff.mm3(diff.tissue(Material::Pulp).removed);
  s.pulp_exposed = diff.pulp_exposed;
  s.exposed_pulp_voxels = diff.exposed_pulp_voxels;
  return s;
}

// ---- 2. cavity preparation -----------------------------------------------------------------------

Result<CavityScore> scoreCavityPreparation(const ToothDiff& diff, const SessionStats& stats, const Task& task) {
  if (!diff.has_ideal) return makeError("", "cavity preparation needs the ideal (the professional's final tooth)");
  const TissueAmounts all = diff.total();
  if (all.ideal_cavity == 0)
    return makeError("", "the ideal cavity is empty: the ideal tooth removed nothing from the initial one");
  const CavityTask& c = task.cavity;
  CavityScore s;
  const double ideal = double(all.ideal_cavity);
  // Fill units stand for volume, so the ratio of units is the ratio of volumes.
  s.undercut_percent = double(all.undercut) * 100.0 / ideal;
  s.overcut_percent = double(all.overcut) * 100.0 / ideal;
  s.nothing_removed = all.removed == 0;
  // An attempt that removed nothing earns nothing: without it, not touching the tooth would score
  // 75 (no over-cut, no tilt, no time).
  if (!s.nothing_removed) {
    s.undercut = clampScore(25.0 - double(all.undercut) * c.undercut_coefficient * 100.0 / ideal, 0.0, 25.0);
    s.overcut = clampScore(25.0 - double(all.overcut) * c.overcut_coefficient * 100.0 / ideal, 0.0, 25.0);
    s.parallel = clampScore(25.0 - double(stats.parallel_over) * c.parallel_coefficient, 0.0, 25.0);
    s.time = clampScore(25.0 - std::max(0.0, stats.elapsed_s - task.target_s) * c.time_coefficient / 60.0, 0.0, 25.0);
  }
  s.total = s.undercut + s.overcut + s.parallel + s.time;
  s.ideal_mm3 = diff.mm3(all.ideal_cavity);
  s.removed_mm3 = diff.mm3(all.removed);
  s.undercut_mm3 = diff.mm3(all.undercut);
  s.overcut_mm3 = diff.mm3(all.overcut);
  s.overcut_near_mm3 = diff.mm3(all.overcut_near);
  s.overcut_gross_mm3 = diff.mm3(all.overcut_gross);
  s.pulp_exposed = diff.pulp_exposed;
  s.exposed_pulp_voxels = diff.exposed_pulp_voxels;
  return s;
}

// ---- 3. the report -------------------------------------------------------------------------------

namespace {

using ojson = nlohmann::ordered_json;

constexpr const char* kReportFormat = "dentsim-score";
constexpr int kReportVersion = 1;

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
  in["ideal"] = file(inputs.ideal);
  in["session"] = file(inputs.session);
  j["inputs"] = std::move(in);
  return j;
}

// Per tissue [mm^3] and in fill units, so a reader can check sums exactly.
ojson volumesJson(const ToothDiff& diff) {
  ojson j = ojson::object();
  j["voxel_mm"] = diff.voxel_mm;
  j["fill_unit_mm3"] = diff.mm3(1);
  auto one = [&](const TissueAmounts& a) {
    ojson t = ojson::object();
    t["initial_mm3"] = diff.mm3(a.initial);
    t["remaining_mm3"] = diff.mm3(a.remaining);
    t["removed_mm3"] = diff.mm3(a.removed);
    if (diff.has_ideal) {
      t["ideal_cavity_mm3"] = diff.mm3(a.ideal_cavity);
      t["undercut_mm3"] = diff.mm3(a.undercut);
      t["overcut_mm3"] = diff.mm3(a.overcut);
      t["overcut_near_mm3"] = diff.mm3(a.overcut_near);
      t["overcut_gross_mm3"] = diff.mm3(a.overcut_gross);
    }
    t["units"] = {{"initial", a.initial}, {"remaining", a.remaining}, {"removed", a.removed}};
    if (diff.has_ideal) {
      t["units"]["ideal_cavity"] = a.ideal_cavity;
      t["units"]["undercut"] = a.undercut;
      t["units"]["overcut"] = a.overcut;
      t["units"]["overcut_near"] = a.overcut_near;
      t["units"]["overcut_gross"] = a.overcut_gross;
    }
    return t;
  };
  for (size_t t = 0; t < kScoredTissues.size(); ++t) j[materialName(kScoredTissues[t])] = one(diff.tissues[t]);
  j["all"] = one(diff.total());
  if (diff.has_ideal) j["leeway_mm"] = diff.leeway_mm;
  j["pulp_exposed"] = diff.pulp_exposed;
  j["exposed_pulp_voxels"] = diff.exposed_pulp_voxels;
  return j;
}

ojson sessionJson(const SessionStats& s) {
  ojson j = ojson::object();
  j["rate_hz"] = s.rate_hz;
  j["steps"] = s.steps;
  j["lost_steps"] = s.lost_steps;
  j["elapsed_s"] = s.elapsed_s;
  j["contact_samples"] = s.contact_samples;
  j["force_over"] = s.force_over;
  j["parallel_over"] = s.parallel_over;
  j["max_force_n"] = s.max_force_n;
  j["max_tilt_deg"] = s.max_tilt_deg;
  return j;
}

}  // namespace

ojson scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff, const SessionStats& stats,
                      const CariesScore& s) {
  ojson j = header(task, inputs);
  const TissueAmounts& caries = diff.tissue(Material::Caries);
  ojson c = ojson::object();
  c["removal"] = {{"points", s.removal},
                  {"max", 50},
                  {"formula", "50 * caries_removed / caries_initial"},
                  {"caries_removed_mm3", s.caries_removed_mm3},
                  {"caries_initial_mm3", s.caries_initial_mm3},
                  {"removed_fraction", s.removed_fraction}};
  c["time"] = {{"points", s.time},
               {"max", 25},
               {"formula", "25 * (failure_s - elapsed_s) / (failure_s - target_s), in [0, 25]; 0 if no caries removed"},
               {"elapsed_s", stats.elapsed_s},
               {"target_s", task.target_s},
               {"failure_s", task.failure_s},
               {"caries_removed", caries.removed > 0}};
  c["force"] = {{"points", s.force},
                {"max", 25},
                {"formula", "25 * (contact_samples - force_over) / contact_samples, in [0, 25]; 0 without contact"},
                {"contact_samples", stats.contact_samples},
                {"force_over", stats.force_over},
                {"force_error_n", task.force_error_n}};
  j["components"] = std::move(c);
  j["total"] = s.total;
  j["healthy_removed_mm3"] = {
      {"enamel", s.enamel_removed_mm3}, {"dentin", s.dentin_removed_mm3}, {"pulp", s.pulp_removed_mm3}};
  j["caries_remaining_mm3"] = s.caries_remaining_mm3;
  j["pulp_exposed"] = s.pulp_exposed;
  j["volumes"] = volumesJson(diff);
  j["session"] = sessionJson(stats);
  return j;
}

ojson scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff, const SessionStats& stats,
                      const CavityScore& s) {
  ojson j = header(task, inputs);
  const CavityTask& t = task.cavity;
  ojson c = ojson::object();
  c["undercut"] = {{"points", s.undercut},
                   {"max", 25},
                   {"formula", "25 - undercut * coefficient * 100 / ideal, in [0, 25]"},
                   {"undercut_mm3", s.undercut_mm3},
                   {"ideal_mm3", s.ideal_mm3},
                   {"percent_of_ideal", s.undercut_percent},
                   {"coefficient", t.undercut_coefficient}};
  c["overcut"] = {{"points", s.overcut},
                  {"max", 25},
                  {"formula", "25 - overcut * coefficient * 100 / ideal, in [0, 25]"},
                  {"overcut_mm3", s.overcut_mm3},
                  {"overcut_near_mm3", s.overcut_near_mm3},
                  {"overcut_gross_mm3", s.overcut_gross_mm3},
                  {"leeway_mm", diff.leeway_mm},
                  {"ideal_mm3", s.ideal_mm3},
                  {"percent_of_ideal", s.overcut_percent},
                  {"coefficient", t.overcut_coefficient}};
  c["parallel"] = {{"points", s.parallel},
                   {"max", 25},
                   {"formula", "25 - parallel_over * coefficient, in [0, 25]"},
                   {"parallel_over", stats.parallel_over},
                   {"contact_samples", stats.contact_samples},
                   {"parallel_error_deg", t.parallel_error_deg},
                   {"insertion_axis", {t.insertion_axis.x, t.insertion_axis.y, t.insertion_axis.z}},
                   {"coefficient", t.parallel_coefficient}};
  c["time"] = {{"points", s.time},
               {"max", 25},
               {"formula", "25 - max(0, elapsed_s - target_s) * coefficient / 60, in [0, 25]"},
               {"elapsed_s", stats.elapsed_s},
               {"target_s", task.target_s},
               {"coefficient", t.time_coefficient}};
  j["components"] = std::move(c);
  j["nothing_removed"] = s.nothing_removed;
  j["total"] = s.total;
  j["removed_mm3"] = s.removed_mm3;
  j["pulp_exposed"] = s.pulp_exposed;
  j["volumes"] = volumesJson(diff);
  j["session"] = sessionJson(stats);
  return j;
}

}  // namespace dentsim
