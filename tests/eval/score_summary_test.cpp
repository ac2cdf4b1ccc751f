// The score report's typed summary: written and read back unchanged, a missing key named, and the golden demo's score.json read as the readers see it.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "eval/score_summary.h"
#include "eval/tooth_diff.h"

namespace dentsim {
namespace {

using ojson = nlohmann::ordered_json;

// A cavity attempt with every optional key set, so that each one travels through the round trip.
ScoreReportSummary fullSummary() {
  ScoreReportSummary s;
  s.task_name = "class1_cavity";
  s.task_title = "Class I";
  s.task_kind = "cavity";
  s.total = 47.0;
  s.total_max = 75.0;
  s.paper_total = 62.5;
  s.completion_share = 0.8;
  ScoreReportPart undercut;
  undercut.name = "undercut";
  undercut.has_points = true;
  undercut.points = 5.0;
  undercut.max = 25.0;
  ScoreReportPart time;  // not scored: its points are null
  time.name = "time";
  time.has_points = true;
  time.max = 25.0;
  time.table_points = 20.0;
  time.earned_share = 0.8;
  ScoreReportPart force;
  force.name = "force";
  force.deduction = true;
  force.has_points = true;
  force.points = 3.0;
  ScoreReportPart cap;
  cap.name = "pulp_exposure";
  cap.deduction = true;
  cap.cap = 50.0;
  cap.applied = false;
  s.parts = {undercut, time, force, cap};
  for (size_t t = 0; t < s.removed_mm3.size(); ++t) s.removed_mm3[t] = 0.5 * double(t + 1);
  s.overcut_mm3 = 0.75;
  s.undercut_mm3 = 1.25;
  s.healthy_outside_zone_mm3 = 0.25;
  s.caries_remaining_mm3 = 0.125;
  s.pulp_exposed = true;
  s.session = ScoreReportSession{271.5, 400, 100, 4.5, 1.25};
  s.agreement = ScoreReportAgreement{0.2, 1200, 62.5, 20.0, 17.5};
  s.guided = ScoreReportGuide{"pro.dses", "00000000deadbeef", 1.0, 2.5};
  s.statement_id = "0b6c6a57-2f7e-5b2e-9d1a-3c6f2e1d4a01";
  s.student = "s1001";
  s.timestamp = "2026-11-27T07:00:00Z";
  return s;
}

TEST(ScoreReportSummary, RoundTripsThroughItsJson) {
  const ScoreReportSummary s = fullSummary();
  auto back = ScoreReportSummary::fromJson(s.toJson());
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(*back, s);
  // And with every optional key left out.
  ScoreReportSummary bare;
  bare.task_name = "caries_removal";
  bare.total = 12.5;
  auto bare_back = ScoreReportSummary::fromJson(bare.toJson());
  ASSERT_TRUE(bare_back.ok()) << bare_back.message();
  EXPECT_EQ(*bare_back, bare);
}

// The keys task validation reads sit where scores.cpp writes them, so a whole report and its cut-down
// one read alike.
TEST(ScoreReportSummary, WritesValidationsKeysAtTheReportsPaths) {
  const ojson j = fullSummary().toJson();
  EXPECT_EQ(j["paper_total"], 62.5);
  EXPECT_EQ(j["completion"]["share"], 0.8);
  EXPECT_EQ(j["components"]["time"]["table_points"], 20.0);
  EXPECT_FALSE(j["components"]["undercut"].contains("table_points"));
  // A report without them (a part not earned in proportion, an older report) reads as none.
  ojson older = j;
  older.erase("paper_total");
  older.erase("completion");
  older["components"]["time"]["table_points"] = nullptr;
  auto s = ScoreReportSummary::fromJson(older);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_FALSE(s->paper_total);
  EXPECT_FALSE(s->completion_share);
  EXPECT_FALSE(s->parts[1].table_points);
}

TEST(ScoreReportSummary, AMissingOrBadKeyIsNamed) {
  const ojson whole = fullSummary().toJson();
  ojson no_total = whole;
  no_total.erase("total");
  EXPECT_EQ(ScoreReportSummary::fromJson(no_total).message(), "total: missing or not a number in [0, 100]");
  ojson no_task = whole;
  no_task["task"].erase("name");
  EXPECT_EQ(ScoreReportSummary::fromJson(no_task).message(), "task.name: missing or not a string");
  ojson other = whole;
  other["format"] = "dentsim-params";
  EXPECT_EQ(ScoreReportSummary::fromJson(other).message(), "format: missing or not \"dentsim-score\"");
  ojson bad_pulp = whole;
  bad_pulp["pulp_exposed"] = "yes";
  EXPECT_EQ(ScoreReportSummary::fromJson(bad_pulp).message(), "pulp_exposed: not true or false");
  ojson bad_id = whole;
  bad_id["statement_id"] = 7;
  EXPECT_EQ(ScoreReportSummary::fromJson(bad_id).message(), "statement_id: not a string");
}

// A caries removal has no ideal: its over-cut is the healthy tissue outside the zone, its under-cut
// the caries left; a cavity's are measured against its ideal.
TEST(ScoreReportSummary, CutsBeyondAndShortFollowTheKindOfReport) {
  ScoreReportSummary s = fullSummary();
  EXPECT_EQ(s.overcutOrHealthyOutsideMm3(), std::optional<double>(0.75));
  EXPECT_EQ(s.undercutOrCariesLeftMm3(), std::optional<double>(1.25));
  s.overcut_mm3.reset();
  s.undercut_mm3.reset();
  EXPECT_EQ(s.overcutOrHealthyOutsideMm3(), std::optional<double>(0.25));
  EXPECT_EQ(s.undercutOrCariesLeftMm3(), std::optional<double>(0.125));
}

// The level-7 demo's report as `replay` writes it (tests/golden): every key the readers use is there.
TEST(ScoreReportSummary, ReadsTheGoldenDemoReport) {
  std::ifstream in(std::string(DENTSIM_SOURCE_DIR) + "/tests/golden/level7_demo/score.json");
  ASSERT_TRUE(in) << "tests/golden/level7_demo/score.json";
  const ojson report = ojson::parse(in);
  auto s = ScoreReportSummary::fromJson(report);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->task_name, "caries_removal");
  EXPECT_EQ(s->task_kind, "caries");
  EXPECT_EQ(s->total, report["total"].get<double>());
  EXPECT_EQ(s->total_max, std::optional<double>(100.0));
  EXPECT_FALSE(s->pulp_exposed);
  EXPECT_FALSE(s->guided);
  EXPECT_FALSE(s->agreement);  // a caries removal has no ideal cavity to agree with
  // Three components (removal, time, force), then the healthy deduction and the pulp cap.
  ASSERT_EQ(s->parts.size(), 5u);
  EXPECT_EQ(s->parts[0].name, "removal");
  EXPECT_EQ(s->parts[1].earned_share, report["components"]["time"]["earned_share"].get<double>());
  EXPECT_EQ(s->parts[1].table_points, report["components"]["time"]["table_points"].get<double>());
  EXPECT_FALSE(s->parts[0].table_points);  // the removal is the work done itself
  EXPECT_EQ(s->paper_total, report["paper_total"].get<double>());
  EXPECT_EQ(s->completion_share, report["completion"]["share"].get<double>());
  EXPECT_TRUE(s->parts[3].deduction);
  EXPECT_EQ(s->parts[4].applied, std::optional<bool>(false));
  // Every tissue of the tooth; the demo's tooth has no neighbour, so its report has none.
  for (size_t t = 0; t < kScoredTissues.size(); ++t) EXPECT_EQ(s->removed_mm3[t].has_value(), isToothTissue(kScoredTissues[t])) << t;
  EXPECT_FALSE(s->adjacent_removed_mm3);
  EXPECT_FALSE(s->overcut_mm3);  // no ideal: no over-cut of one
  EXPECT_EQ(s->overcutOrHealthyOutsideMm3(), report["zones"]["healthy_outside_zone_mm3"].get<double>());
  EXPECT_EQ(s->undercutOrCariesLeftMm3(), report["caries_remaining_mm3"].get<double>());
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->contact_samples, std::optional<uint64_t>(65357));
  EXPECT_EQ(s->session->elapsed_s, report["session"]["elapsed_s"].get<double>());
  // Its cut-down report reads back to the same summary.
  auto again = ScoreReportSummary::fromJson(s->toJson());
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(*again, *s);
}

}  // namespace
}  // namespace dentsim
