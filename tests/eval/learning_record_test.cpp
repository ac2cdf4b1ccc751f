// Learning records: each statement field against values worked out by hand from a small score report, the parts it carries, the verb by pass mark, and the ids' stability.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "eval/learning_record.h"

namespace dentsim {
namespace {

using ojson = nlohmann::ordered_json;

// RFC 4122's DNS namespace example as Python's uuid.uuid5 computes it, and dentsim's own ids.
TEST(LearningRecord, NameBasedUuidsMatchAnotherImplementation) {
  EXPECT_EQ(uuidV5("6ba7b810-9dad-11d1-80b4-00c04fd430c8", "www.example.com"), "2ed6657d-e927-568b-95e1-2665a8aea6a2");
  // uuid5(uuid5(NAMESPACE_URL, "https://dentsim.invalid/xapi"), "00000000deadbeef|caries_removal|s1001")
  EXPECT_EQ(statementId("00000000deadbeef", "caries_removal", "s1001"), "261775e1-3f12-53b7-9d74-a43433b0afd1");
  EXPECT_EQ(statementId("00000000deadbeef", "caries_removal", "s1002"), "38ea6b91-fd77-56d6-ba91-4f0ee396cf08");
}

TEST(LearningRecord, DurationsAreIso8601WithCentiseconds) {
  EXPECT_EQ(isoDuration(0), "PT0S");
  EXPECT_EQ(isoDuration(12.5), "PT12.5S");
  EXPECT_EQ(isoDuration(75.25), "PT1M15.25S");
  EXPECT_EQ(isoDuration(3600), "PT1H0S");
  EXPECT_EQ(isoDuration(59.999), "PT1M0S");  // rounded to centiseconds before splitting
  EXPECT_EQ(isoDuration(3723.04), "PT1H2M3.04S");
}

TEST(LearningRecord, OneRuleForTheActivityIris) {
  EXPECT_EQ(taskActivityIri("https://school.example/xapi/", "endo-2026", "access_cavity"),
            "https://school.example/xapi/courses/endo-2026/tasks/access_cavity");
  EXPECT_EQ(courseActivityIri("https://school.example/xapi", "endo-2026"), "https://school.example/xapi/courses/endo-2026");
  EXPECT_EQ(extensionIri("force"), "https://dentsim.invalid/xapi/extensions/force");
}

Task cariesTask() {
  Task t;
  t.name = "caries_removal";
  t.kind = TaskKind::Caries;
  t.title = "Remove the caries";
  t.instructions = "Open the lesion and remove the caries.";
  t.force_error_n = 3.0;
  t.pass_mark = 70.0;
  return t;
}

// A caries report as scores.cpp writes it, cut down to the keys the statement reads.
ojson cariesReport(double total) {
  ojson r = ojson::object();
  r["format"] = "dentsim-score";
  r["task"] = {{"name", "caries_removal"}};
  r["total"] = total;
  r["total_max"] = 100.0;
  r["caries_remaining_mm3"] = 0.25;
  r["pulp_exposed"] = false;
  r["zones"] = {{"healthy_outside_zone_mm3", 0.5}};
  r["volumes"] = ojson::object();
  r["volumes"]["enamel"] = {{"removed_mm3", 1.5}};
  r["volumes"]["dentin"] = {{"removed_mm3", 2.0}};
  r["volumes"]["pulp"] = {{"removed_mm3", 0.0}};
  r["volumes"]["caries"] = {{"removed_mm3", 4.75}};
  r["volumes"]["all"] = {{"removed_mm3", 8.25}};
  r["session"] = {{"elapsed_s", 95.5}, {"contact_samples", 400}, {"force_over", 100}, {"max_force_n", 4.5}, {"mean_force_n", 1.25}};
  return r;
}

LearnerContext learner() {
  LearnerContext l;
  l.student = "s1001";
  l.student_name = "Ada Lovelace";
  l.home_page = "https://school.example";
  l.course = "cons-101";
  l.activity_base = "https://school.example/xapi";
  l.language = "en-GB";
  return l;
}

AttemptFacts facts() {
  AttemptFacts f;
  f.attempt_key = "00000000deadbeef";
  f.session_hash = "00000000deadbeef";
  f.timestamp = "2026-11-27T07:00:00Z";
  return f;
}

TEST(LearningRecord, StatementHoldsTheActorVerbObjectResultAndContext) {
  auto s = buildStatement(cariesTask(), cariesReport(82.5), learner(), facts());
  ASSERT_TRUE(s.ok()) << s.message();
  const ojson& j = *s;
  EXPECT_EQ(j["id"], "261775e1-3f12-53b7-9d74-a43433b0afd1");
  EXPECT_EQ(j["actor"]["objectType"], "Agent");
  EXPECT_EQ(j["actor"]["name"], "Ada Lovelace");
  EXPECT_EQ(j["actor"]["account"]["homePage"], "https://school.example");
  EXPECT_EQ(j["actor"]["account"]["name"], "s1001");
  EXPECT_EQ(j["verb"]["id"], "http://adlnet.gov/expapi/verbs/passed");  // 82.5 >= 70
  EXPECT_EQ(j["object"]["id"], "https://school.example/xapi/courses/cons-101/tasks/caries_removal");
  EXPECT_EQ(j["object"]["definition"]["name"]["en-GB"], "Remove the caries");
  EXPECT_EQ(j["object"]["definition"]["description"]["en-GB"], "Open the lesion and remove the caries.");
  const ojson& r = j["result"];
  EXPECT_EQ(r["score"]["raw"], 82.5);
  EXPECT_EQ(r["score"]["scaled"], 0.825);
  EXPECT_EQ(r["score"]["min"], 0);
  EXPECT_EQ(r["score"]["max"], 100);
  EXPECT_EQ(r["success"], true);
  EXPECT_EQ(r["completion"], true);
  EXPECT_EQ(r["duration"], "PT1M35.5S");
  const ojson& e = r["extensions"];
  const ojson& removed = e["https://dentsim.invalid/xapi/extensions/removed-mm3"];
  EXPECT_EQ(removed["enamel"], 1.5);
  EXPECT_EQ(removed["caries"], 4.75);
  // A caries removal: the over-cut is the healthy tissue outside the zone, the under-cut the caries left.
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/overcut-mm3"], 0.5);
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/undercut-mm3"], 0.25);
  const ojson& force = e["https://dentsim.invalid/xapi/extensions/force"];
  EXPECT_EQ(force["mean_n"], 1.25);
  EXPECT_EQ(force["max_n"], 4.5);
  EXPECT_EQ(force["over_threshold_fraction"], 0.25);  // 100 of 400 contact samples
  EXPECT_EQ(force["threshold_n"], 3.0);
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/guided"], false);
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/session-hash"], "00000000deadbeef");
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/pulp-exposed"], false);
  const ojson& c = j["context"];
  EXPECT_EQ(c["platform"], "dentsim");
  EXPECT_EQ(c["language"], "en-GB");
  EXPECT_EQ(c["contextActivities"]["parent"][0]["id"], "https://school.example/xapi/courses/cons-101");
  EXPECT_EQ(c["extensions"]["https://dentsim.invalid/xapi/extensions/course"], "cons-101");
  EXPECT_EQ(j["timestamp"], "2026-11-27T07:00:00Z");
}

TEST(LearningRecord, VerbFollowsThePassMark) {
  Task t = cariesTask();
  auto failed = buildStatement(t, cariesReport(69.99), learner(), facts());
  ASSERT_TRUE(failed.ok());
  EXPECT_EQ((*failed)["verb"]["id"], "http://adlnet.gov/expapi/verbs/failed");
  EXPECT_EQ((*failed)["result"]["success"], false);
  auto at_mark = buildStatement(t, cariesReport(70.0), learner(), facts());
  EXPECT_EQ((*at_mark)["verb"]["id"], "http://adlnet.gov/expapi/verbs/passed");
  t.pass_mark.reset();
  auto completed = buildStatement(t, cariesReport(20.0), learner(), facts());
  EXPECT_EQ((*completed)["verb"]["id"], "http://adlnet.gov/expapi/verbs/completed");
  EXPECT_FALSE((*completed)["result"].contains("success"));
  EXPECT_EQ((*completed)["result"]["completion"], true);
}

TEST(LearningRecord, CavityReportsGiveTheirOwnCutsAndNoSessionGivesNoForce) {
  Task t = cariesTask();
  t.kind = TaskKind::Cavity;
  ojson r = cariesReport(50);
  r["volumes"]["all"]["overcut_mm3"] = 0.75;
  r["volumes"]["all"]["undercut_mm3"] = 1.25;
  r["session"] = {{"missing", "no session was given"}};
  AttemptFacts f = facts();
  f.session_hash.reset();
  auto s = buildStatement(t, r, learner(), f);
  ASSERT_TRUE(s.ok()) << s.message();
  const ojson& e = (*s)["result"]["extensions"];
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/overcut-mm3"], 0.75);
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/undercut-mm3"], 1.25);
  EXPECT_TRUE(e["https://dentsim.invalid/xapi/extensions/force"].is_null());
  EXPECT_TRUE(e["https://dentsim.invalid/xapi/extensions/session-hash"].is_null());
  EXPECT_FALSE((*s)["result"].contains("duration"));  // no session, no elapsed time
}

// The parts, as the class report reads them: each component's points and max, each deduction's
// points or its cap, and no formula; a cavity's surface agreement without its walls.
TEST(LearningRecord, ResultCarriesThePartsAndTheSurfaceAgreement) {
  Task t = cariesTask();
  t.kind = TaskKind::Cavity;
  ojson r = cariesReport(52);
  r["components"] = ojson::parse(R"({"undercut":{"points":5,"max":25,"formula":"25 * ...","undercut_mm3":1.25},"time":{"points":null,"max":25}})");
  r["deductions"] = ojson::parse(R"({"force":{"points":3,"coefficient":1},"pulp_exposure":{"pulp_exposed":false,"cap":50,"cap_of_100":50,"applied":false}})");
  r["surface_agreement"] = ojson::parse(R"({"band_mm":0.2,"within_percent":62.5,"beyond_percent":20,"short_percent":17.5,"walls":{"mesial":{}}})");
  auto s = buildStatement(t, r, learner(), facts());
  ASSERT_TRUE(s.ok()) << s.message();
  const ojson& e = (*s)["result"]["extensions"];
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/parts"],
            ojson::parse(R"({"components":{"undercut":{"points":5,"max":25},"time":{"points":null,"max":25}},)"
                         R"("deductions":{"force":{"points":3},"pulp_exposure":{"cap":50,"applied":false}}})"));
  EXPECT_EQ(e["https://dentsim.invalid/xapi/extensions/surface-agreement"],
            ojson::parse(R"({"band_mm":0.2,"within_percent":62.5,"beyond_percent":20,"short_percent":17.5})"));
  // A caries report has no agreement, and its statement no such key.
  auto caries = buildStatement(cariesTask(), cariesReport(80), learner(), facts());
  ASSERT_TRUE(caries.ok());
  EXPECT_FALSE((*caries)["result"]["extensions"].contains("https://dentsim.invalid/xapi/extensions/surface-agreement"));
  EXPECT_TRUE((*caries)["result"]["extensions"]["https://dentsim.invalid/xapi/extensions/parts"].is_null());  // cut down: no parts
}

TEST(LearningRecord, SameAttemptSameIdAndAnyChangeAnother) {
  const auto a = buildStatement(cariesTask(), cariesReport(80), learner(), facts());
  AttemptFacts later = facts();
  later.timestamp = "2026-11-28T07:00:00Z";  // scored again the next day
  const auto b = buildStatement(cariesTask(), cariesReport(80), learner(), later);
  EXPECT_EQ((*a)["id"], (*b)["id"]);
  LearnerContext other = learner();
  other.student = "s1002";
  EXPECT_NE((*a)["id"], (*buildStatement(cariesTask(), cariesReport(80), other, facts()))["id"]);
  AttemptFacts another = facts();
  another.attempt_key = "00000000deadbeee";
  EXPECT_NE((*a)["id"], (*buildStatement(cariesTask(), cariesReport(80), learner(), another))["id"]);
}

TEST(LearningRecord, MissingPiecesAreNamed) {
  LearnerContext nobody = learner();
  nobody.student.clear();
  EXPECT_EQ(buildStatement(cariesTask(), cariesReport(80), nobody, facts()).message(),
            "learning record: no student (give --student or \"student\" in the config)");
  LearnerContext bad_course = learner();
  bad_course.course = "a b";
  EXPECT_NE(buildStatement(cariesTask(), cariesReport(80), bad_course, facts()).message().find("course \"a b\" is not a plain name"),
            std::string::npos);
  ojson no_total = cariesReport(80);
  no_total.erase("total");
  EXPECT_EQ(buildStatement(cariesTask(), no_total, learner(), facts()).message(),
            "learning record: the score report's total: missing or not a number in [0, 100]");
}

}  // namespace
}  // namespace dentsim
