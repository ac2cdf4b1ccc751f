// Tests of the score screen's rows: the same parts, points and deductions as the score's report, for either kind of task, with or without a session.
#include "ui/score_rows.h"

#include <gtest/gtest.h>

#include <cstdarg>
#include <cstdio>

#include "eval/eval_fixtures.h"

namespace dentsim {
namespace {

// Enamel over dentin with a little caries, and the same with the caries and some enamel beside it
// drilled out: a caries removal that cut healthy tissue outside the zone.
ToothVolume slab(bool cut) {
  ToothVolume t = test::emptyTooth();
  test::setBox(t, {0, 0, 0}, {16, 16, 6}, makeVoxel(Material::Dentin));
  test::setBox(t, {0, 0, 6}, {16, 16, 8}, makeVoxel(Material::Enamel));
  test::setBox(t, {4, 4, 7}, {8, 6, 8}, makeVoxel(Material::Caries));
  if (cut) test::setBox(t, {4, 4, 7}, {12, 6, 8}, Voxel{0});
  return t;
}

// The attribute has the compiler check each call's literal format against its arguments.
__attribute__((format(printf, 1, 2))) std::string fixed(const char* format, ...) {
  char text[64];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  return text;
}

TEST(ScoreRows, EachPartAndScoredDeductionOfTheReportInItsOrder) {
  const Task task = test::cariesTask();
  auto score = scoreCut(task, slab(false), slab(true), nullptr, nullptr, scoreFiles("a.dvol", "b.dvol", ""));
  ASSERT_TRUE(score.ok()) << score.message();
  const ui::ScoreSummary s = ui::scoreSummaryOf(*score);
  EXPECT_TRUE(s.valid);
  EXPECT_EQ(s.total, score->total);
  EXPECT_EQ(s.total_max, 50.0);  // no session: time and force not scored
  std::vector<ui::ScoreRow> expected;
  for (const auto& [name, part] : score->report["components"].items())
    expected.push_back({name, part["points"].is_number() ? fixed("%.1f / ", part["points"].get<double>()) +
                                                               std::to_string(part["max"].get<int>())
                                                         : "not scored"});
  for (const auto& [name, part] : score->report["deductions"].items())
    if (part.contains("points") && part["points"].is_number()) expected.push_back({name, fixed("-%.1f", part["points"].get<double>())});
  expected.push_back({"caries left", fixed("%.3f mm^3", score->report["caries_remaining_mm3"].get<double>())});
  expected.push_back({"pulp exposed", "no"});
  ASSERT_EQ(s.rows.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(s.rows[i].label, expected[i].label) << i;
    EXPECT_EQ(s.rows[i].value, expected[i].value) << i;
  }
  // The cut took healthy enamel outside the zone: the deduction is a real number on the screen.
  EXPECT_EQ(s.rows[1].value, "not scored");
  EXPECT_NE(s.rows[3].value, "-0.0");
}

TEST(ScoreRows, ACavityShowsItsFourPartsAndNoCariesRow) {
  SessionScore score;
  score.total = 61.25;
  score.lines = {{"undercut", 20.0, 25.0, false, {}},
                 {"overcut", 18.25, 25.0, false, {}},
                 {"parallel", std::nullopt, 25.0, false, {}},
                 {"time", std::nullopt, 25.0, false, {}},
                 {"force", std::nullopt, 0.0, true, {}}};
  score.pulp_exposed = true;
  const ui::ScoreSummary s = ui::scoreSummaryOf(score);
  ASSERT_EQ(s.rows.size(), 5u);
  EXPECT_EQ(s.rows[0].value, "20.0 / 25");
  EXPECT_EQ(s.rows[1].value, "18.2 / 25");  // printf rounds 18.25 to even in binary: 18.2
  EXPECT_EQ(s.rows[2].value, "not scored");
  EXPECT_EQ(s.rows[3].label, "time");
  EXPECT_EQ(s.rows[4].label, "pulp exposed");  // the unscored force deduction shows no row
  EXPECT_EQ(s.rows[4].value, "yes");
}

// A crown's criterion leads with what was measured against its range, then its points.
TEST(ScoreRows, ACrownCriterionShowsItsMeasurementBeforeItsPoints) {
  SessionScore score;
  score.total = 85.0;
  score.lines = {{"taper", 0.0, 15.0, false, "0.0 deg mesiodistal (10-20 deg) outside"}};
  const ui::ScoreSummary s = ui::scoreSummaryOf(score);
  ASSERT_EQ(s.rows.size(), 2u);
  EXPECT_EQ(s.rows[0].label, "taper");
  EXPECT_EQ(s.rows[0].value, "0.0 deg mesiodistal (10-20 deg) outside  0.0 / 15");
}

}  // namespace
}  // namespace dentsim
