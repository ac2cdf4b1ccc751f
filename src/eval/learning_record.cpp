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

// A number the report may not have (a part not scored) as the statement writes it: null when none.
template <typename Number>
ojson orNull(const std::optional<Number>& v) {
  return v ? ojson(*v) : ojson(nullptr);
}

// The score's parts as the class report reads them (eval/attempt_reader.h, readParts): each
// component's points, max and earned share (a part earned in proportion to the work done), each
// deduction's points, or its cap and whether it applied. The formulas and the values they use stay
// in the score report. Null when the report lists no parts.
ojson partsOf(const ScoreReportSummary& score) {
  if (score.parts.empty()) return nullptr;
  ojson components = ojson::object(), deductions = ojson::object();
  for (const ScoreReportPart& p : score.parts) {
    ojson kept = ojson::object();
    if (p.has_points) kept["points"] = orNull(p.points);
    if (p.deduction) {
      if (p.cap) kept["cap"] = *p.cap;
      if (p.applied) kept["applied"] = *p.applied;
      deductions[p.name] = std::move(kept);
    } else {
      if (p.max) kept["max"] = *p.max;
      if (p.earned_share) kept["earned_share"] = *p.earned_share;
      components[p.name] = std::move(kept);
    }
  }
  return {{"components", std::move(components)}, {"deductions", std::move(deductions)}};
}

// The surface agreement's shares (the per-wall figures stay in the report); null when the report has none.
ojson surfaceAgreementOf(const ScoreReportSummary& score) {
  if (!score.agreement) return nullptr;
  const ScoreReportAgreement& a = *score.agreement;
  ojson out = ojson::object();
  out["band_mm"] = a.band_mm;
  if (a.samples) out["samples"] = *a.samples;
  out["within_percent"] = a.within_percent;
  if (a.beyond_percent) out["beyond_percent"] = *a.beyond_percent;
  if (a.short_percent) out["short_percent"] = *a.short_percent;
  return out;
}

// The extensions a teacher's report reads: what was cut, how hard, on which session, and why it scored so.
ojson resultExtensions(const Task& task, const ScoreReportSummary& score, const AttemptFacts& facts) {
  ojson removed = ojson::object();
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    // A neighbour's entry only where the report has one: a tooth without neighbours keeps its statement.
    if (isToothTissue(kScoredTissues[t]) || score.removed_mm3[t])
      removed[materialName(kScoredTissues[t])] = orNull(score.removed_mm3[t]);
  ojson force = nullptr;
  if (score.session && score.session->contact_samples) {
    const ScoreReportSession& s = *score.session;
    const uint64_t n = *s.contact_samples;
    force = {{"mean_n", orNull(s.mean_force_n)},
             {"max_n", orNull(s.max_force_n)},
             {"threshold_n", task.force_error_n},
             {"over_threshold_fraction", n > 0 && s.force_over ? ojson(double(*s.force_over) / double(n)) : ojson(0.0)},
             {"contact_samples", n}};
  }
  ojson ext = ojson::object();
  ext[extensionIri("removed-mm3")] = std::move(removed);
  ext[extensionIri("overcut-mm3")] = orNull(score.overcutOrHealthyOutsideMm3());
  ext[extensionIri("undercut-mm3")] = orNull(score.undercutOrCariesLeftMm3());
  ext[extensionIri("force")] = std::move(force);
  // A guided attempt's report names its guide (eval/cut_score.h); an unguided one has none.
  ext[extensionIri("guided")] = score.guided.has_value();
  ext[extensionIri("session-hash")] = orNull(facts.session_hash);
  ext[extensionIri("pulp-exposed")] = score.pulp_exposed;
  if (score.adjacent_removed_mm3) ext[extensionIri("adjacent-damaged")] = score.adjacent_damaged;
  ext[extensionIri("task-kind")] = taskKindName(task.kind);
  ext[extensionIri("total-max")] = orNull(score.total_max);
  ext[extensionIri("parts")] = partsOf(score);
  const ojson agreement = surfaceAgreementOf(score);
  if (!agreement.is_null()) ext[extensionIri("surface-agreement")] = agreement;
  return ext;
}

}  // namespace

Result<ojson> buildStatement(const Task& task, const ojson& report, const LearnerContext& learner, const AttemptFacts& facts) {
  auto score = ScoreReportSummary::fromJson(report);
  if (!score) return Error{"learning record: the score report's " + score.message()};
  return buildStatement(task, *score, learner, facts);
}

Result<ojson> buildStatement(const Task& task, const ScoreReportSummary& score, const LearnerContext& learner,
                             const AttemptFacts& facts) {
  if (learner.student.empty()) return Error{"learning record: no student (give --student or \"student\" in the config)"};
  if (!isPlainName(learner.course))
    return Error{"learning record: course " + quotedForMessage(learner.course) + " is not a plain name (letters, digits, '_', '-', '.')"};
  const double total = score.total;
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
  if (score.session && score.session->elapsed_s) result["duration"] = isoDuration(*score.session->elapsed_s);
  result["extensions"] = resultExtensions(task, score, facts);

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
