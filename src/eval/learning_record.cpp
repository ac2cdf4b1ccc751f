// Learning records: the xAPI statement of a scored attempt and its name-based id.
//
// Sections: 1. UUIDs  2. IRIs, verbs, durations  3. the statement
#include "eval/learning_record.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>

#include <uuid/uuid.h>

#include "eval/tooth_diff.h"
#include "io/strict_json.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. UUIDs ----------------------------------------------------------------------------------------
// The statement id is a version-5 UUID, which any xAPI tool can recompute; XXH3 (io/file_hash)
// would give ids that no other tool could. libuuid makes it.

namespace {
// RFC 4122's namespace for names that are URLs.
constexpr const char* kUrlNamespace = "6ba7b811-9dad-11d1-80b4-00c04fd430c8";
}  // namespace

std::string uuidV5(const std::string& ns, const std::string& name) {
  uuid_t ns_bytes;
  const bool ok = uuid_parse(ns.c_str(), ns_bytes) == 0;
  (void)ok;
  assert(ok && "uuidV5: the namespace is a UUID");
  uuid_t u;
  uuid_generate_sha1(u, ns_bytes, name.data(), name.size());
  char text[37];
  uuid_unparse_lower(u, text);
  return text;
}

std::string statementId(const std::string& attempt_key, const std::string& task, const std::string& student) {
  static const std::string ns = uuidV5(kUrlNamespace, kDefaultActivityBase);
  return uuidV5(ns, attempt_key + "|" + task + "|" + student);
}

// ---- 2. IRIs, verbs, durations ---------------------------------------------------------------------

namespace {
std::string withoutTrailingSlash(std::string s) {
  while (!s.empty() && s.back() == '/') s.pop_back();
  return s;
}
}  // namespace

std::string courseActivityIri(const std::string& activity_base, const std::string& course) {
  return withoutTrailingSlash(activity_base) + "/courses/" + course;
}

std::string taskActivityIri(const std::string& activity_base, const std::string& course, const std::string& task) {
  return courseActivityIri(activity_base, course) + "/tasks/" + task;
}

std::string extensionIri(const std::string& name) { return std::string(kExtensionBase) + name; }

AttemptVerb attemptVerb(const Task& task, double total) {
  if (!task.pass_mark) return AttemptVerb::Completed;
  return total >= *task.pass_mark ? AttemptVerb::Passed : AttemptVerb::Failed;
}

const char* attemptVerbName(AttemptVerb verb) {
  switch (verb) {
    case AttemptVerb::Completed: return "completed";
    case AttemptVerb::Passed: return "passed";
    case AttemptVerb::Failed: return "failed";
  }
  return "completed";
}

std::string isoDuration(double seconds) {
  // Whole centiseconds first, so that 59.999 s becomes "PT1M0S" rather than "PT60S".
  const long long cs = seconds > 0 && std::isfinite(seconds) ? std::llround(seconds * 100.0) : 0;
  const long long hours = cs / 360000, minutes = cs / 6000 % 60, rest_cs = cs % 6000;
  std::string text = "PT";
  if (hours > 0) text += std::to_string(hours) + "H";
  if (minutes > 0) text += std::to_string(minutes) + "M";
  char secs[32];
  if (rest_cs % 100 == 0) std::snprintf(secs, sizeof secs, "%lldS", rest_cs / 100);
  else if (rest_cs % 10 == 0) std::snprintf(secs, sizeof secs, "%lld.%lldS", rest_cs / 100, rest_cs % 100 / 10);
  else std::snprintf(secs, sizeof secs, "%lld.%02lldS", rest_cs / 100, rest_cs % 100);
  return text + secs;
}

// ---- 3. the statement ------------------------------------------------------------------------------

namespace {

using ojson = nlohmann::ordered_json;

// A number at a path of the report, or null where the report has none (a part not scored).
ojson numberAt(const ojson& report, std::initializer_list<const char*> path) {
  const ojson* at = &report;
  for (const char* key : path) {
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
  }
  return at->is_number() ? *at : ojson(nullptr);
}

// The score's parts as the class report reads them (eval/attempt_reader.h, readParts): each
// component's points, max and earned share (a part earned in proportion to the work done), each
// deduction's points, or its cap and whether it applied. The
// formulas and the values they use stay in the score report. Null when the report has neither.
ojson partsOf(const ojson& report) {
  const ojson* components = report.contains("components") ? &report["components"] : nullptr;
  const ojson* deductions = report.contains("deductions") ? &report["deductions"] : nullptr;
  if ((!components || !components->is_object()) && (!deductions || !deductions->is_object())) return nullptr;
  // Only the keys that say what a part earned or cost; a part without them is copied as {}.
  auto cut = [](const ojson* parts, std::initializer_list<const char*> keys) {
    ojson out = ojson::object();
    if (!parts || !parts->is_object()) return out;
    for (const auto& [name, part] : parts->items()) {
      if (!part.is_object()) continue;
      ojson kept = ojson::object();
      for (const char* k : keys)
        if (part.contains(k) && (part[k].is_number() || part[k].is_boolean() || part[k].is_null())) kept[k] = part[k];
      out[name] = std::move(kept);
    }
    return out;
  };
  return {{"components", cut(components, {"points", "max", "earned_share"})},
          {"deductions", cut(deductions, {"points", "cap", "applied"})}};
}

// The surface agreement's shares (the per-wall figures stay in the report); null when the report has none.
ojson surfaceAgreementOf(const ojson& report) {
  if (!report.contains("surface_agreement") || !report["surface_agreement"].is_object()) return nullptr;
  const ojson& sa = report["surface_agreement"];
  ojson out = ojson::object();
  for (const char* k : {"band_mm", "samples", "within_percent", "beyond_percent", "short_percent"})
    if (sa.contains(k) && sa[k].is_number()) out[k] = sa[k];
  return out.contains("band_mm") && out.contains("within_percent") ? out : ojson(nullptr);
}

// The extensions a teacher's report reads: what was cut, how hard, on which session, and why it scored so.
ojson resultExtensions(const Task& task, const ojson& report, const AttemptFacts& facts) {
  ojson removed = ojson::object();
  for (Material m : kScoredTissues) removed[materialName(m)] = numberAt(report, {"volumes", materialName(m).c_str(), "removed_mm3"});
  // A cavity measures against the ideal; a caries removal has no ideal, and its over-cut is the
  // healthy tissue cut outside the allowed zone, its under-cut the caries left standing.
  ojson overcut = numberAt(report, {"volumes", "all", "overcut_mm3"});
  if (overcut.is_null()) overcut = numberAt(report, {"zones", "healthy_outside_zone_mm3"});
  ojson undercut = numberAt(report, {"volumes", "all", "undercut_mm3"});
  if (undercut.is_null()) undercut = numberAt(report, {"caries_remaining_mm3"});
  ojson force = nullptr;
  const ojson contacts = numberAt(report, {"session", "contact_samples"});
  if (!contacts.is_null()) {
    const double n = contacts.get<double>();
    const ojson over = numberAt(report, {"session", "force_over"});
    force = {{"mean_n", numberAt(report, {"session", "mean_force_n"})},
             {"max_n", numberAt(report, {"session", "max_force_n"})},
             {"threshold_n", task.force_error_n},
             {"over_threshold_fraction", n > 0 && over.is_number() ? ojson(over.get<double>() / n) : ojson(0.0)},
             {"contact_samples", contacts}};
  }
  const bool pulp_exposed = report.contains("pulp_exposed") && report["pulp_exposed"].is_boolean() && report["pulp_exposed"].get<bool>();
  ojson ext = ojson::object();
  ext[extensionIri("removed-mm3")] = std::move(removed);
  ext[extensionIri("overcut-mm3")] = std::move(overcut);
  ext[extensionIri("undercut-mm3")] = std::move(undercut);
  ext[extensionIri("force")] = std::move(force);
  // A guided attempt's report names its guide (eval/cut_score.h); an unguided one has none.
  ext[extensionIri("guided")] = report.contains("guided") && report["guided"].is_object();
  ext[extensionIri("session-hash")] = facts.session_hash ? ojson(*facts.session_hash) : ojson(nullptr);
  ext[extensionIri("pulp-exposed")] = pulp_exposed;
  ext[extensionIri("task-kind")] = taskKindName(task.kind);
  ext[extensionIri("total-max")] = numberAt(report, {"total_max"});
  ext[extensionIri("parts")] = partsOf(report);
  const ojson agreement = surfaceAgreementOf(report);
  if (!agreement.is_null()) ext[extensionIri("surface-agreement")] = agreement;
  return ext;
}

}  // namespace

Result<ojson> buildStatement(const Task& task, const ojson& report, const LearnerContext& learner, const AttemptFacts& facts) {
  if (learner.student.empty()) return Error{"learning record: no student (give --student or \"student\" in the config)"};
  if (!isPlainName(learner.course))
    return Error{"learning record: course " + quotedForMessage(learner.course) + " is not a plain name (letters, digits, '_', '-', '.')"};
  const ojson total_json = numberAt(report, {"total"});
  if (total_json.is_null()) return Error{"learning record: the score report has no total"};
  const double total = total_json.get<double>();
  const double raw = std::clamp(total, 0.0, 100.0);
  const AttemptVerb verb = attemptVerb(task, total);
  const std::string& lang = learner.language;

  ojson actor = ojson::object();
  actor["objectType"] = "Agent";
  if (!learner.student_name.empty()) actor["name"] = learner.student_name;
  actor["account"] = {{"homePage", learner.home_page}, {"name", learner.student}};

  ojson definition = ojson::object();
  definition["name"] = {{lang, task.title}};
  if (!task.instructions.empty()) definition["description"] = {{lang, task.instructions}};
  definition["type"] = "http://adlnet.gov/expapi/activities/assessment";

  ojson result = ojson::object();
  // xAPI's scaled score is at most four decimals in many LRSs' eyes; the raw score keeps the rest.
  result["score"] = {{"scaled", std::round(raw / 100.0 * 1e4) / 1e4}, {"raw", raw}, {"min", 0}, {"max", 100}};
  if (verb != AttemptVerb::Completed) result["success"] = verb == AttemptVerb::Passed;
  result["completion"] = true;
  const ojson elapsed = numberAt(report, {"session", "elapsed_s"});
  if (!elapsed.is_null()) result["duration"] = isoDuration(elapsed.get<double>());
  result["extensions"] = resultExtensions(task, report, facts);

  ojson context = ojson::object();
  context["contextActivities"] = {
      {"parent", ojson::array({{{"objectType", "Activity"}, {"id", courseActivityIri(learner.activity_base, learner.course)}}})}};
  context["platform"] = "dentsim";
  context["language"] = lang;
  context["extensions"] = {{extensionIri("course"), learner.course}};

  ojson s = ojson::object();
  s["id"] = statementId(facts.attempt_key, task.name, learner.student);
  s["actor"] = std::move(actor);
  s["verb"] = {{"id", std::string(kVerbBase) + attemptVerbName(verb)}, {"display", {{"en-US", attemptVerbName(verb)}}}};
  s["object"] = {{"objectType", "Activity"},
                 {"id", taskActivityIri(learner.activity_base, learner.course, task.name)},
                 {"definition", std::move(definition)}};
  s["result"] = std::move(result);
  s["context"] = std::move(context);
  s["timestamp"] = facts.timestamp;
  s["version"] = "1.0.3";
  return s;
}

}  // namespace dentsim
