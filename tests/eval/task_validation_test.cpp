// Task validation: which part each fault should cost, the "most in its own part" rule counted by hand, and a short validation of the built-in class I at level 7 with its JSON.
#include "eval/task_validation.h"

#include <gtest/gtest.h>

#include "eval/cut_score.h"
#include "sim/builtin_tooth.h"
#include "test_support.h"

namespace dentsim {
namespace {

TEST(TaskValidation, FaultPartsPerKind) {
  EXPECT_EQ(faultParts(TaskKind::Caries, Attempt::Overcut), std::vector<std::string>{"healthy"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Overcut), std::vector<std::string>{"overcut"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Undercut), std::vector<std::string>{"undercut"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Token), std::vector<std::string>{"undercut"});
  EXPECT_EQ(faultParts(TaskKind::Access, Attempt::Undercut), (std::vector<std::string>{"undercut", "pulp cap"}));
  // A heavy hand drives the bur past the floor: force and what lies beyond the target.
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Heavy), (std::vector<std::string>{"force", "overcut"}));
  EXPECT_EQ(faultParts(TaskKind::Caries, Attempt::Heavy), (std::vector<std::string>{"force", "healthy"}));
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Tilted), std::vector<std::string>{"parallel"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Slow), std::vector<std::string>{"time"});
  EXPECT_TRUE(faultParts(TaskKind::Caries, Attempt::Expert).empty());
  // A crown's faults, each in its criterion of eval/crown_score.h; the cap is the undercut's too.
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::Overtaper), std::vector<std::string>{"taper"});
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::Shallow), std::vector<std::string>{"occlusal_reduction"});
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::WallUndercut), (std::vector<std::string>{"undercut", "undercut cap"}));
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::ThinMargin), std::vector<std::string>{"margin_width"});
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::Nick), std::vector<std::string>{"adjacent"});
  EXPECT_EQ(faultParts(TaskKind::Crown, Attempt::Token).size(), 7u);  // every criterion
  EXPECT_TRUE(faultParts(TaskKind::Cavity, Attempt::Overtaper).empty());
}

TEST(TaskValidation, EachKindRunsItsOwnAttempts) {
  EXPECT_EQ(kindAttempts(TaskKind::Cavity), std::vector<Attempt>(kAttempts.begin(), kAttempts.end()));
  EXPECT_EQ(kindAttempts(TaskKind::Crown), std::vector<Attempt>(kCrownAttempts.begin(), kCrownAttempts.end()));
  EXPECT_EQ(crownAttemptNames(), "expert, overtaper, shallow, wall_undercut, thin_margin, nick, token");
  for (Attempt a : kCrownAttempts) EXPECT_EQ(parseAttempt(attemptName(a)), a);
  EXPECT_EQ(ValidationSettings{}.crown_min_gap, 10.0);
  EXPECT_EQ(ValidationSettings{}.min_gap, 20.0);
}

TEST(TaskValidation, MostInItsOwnPartMeansMoreThanAnyOtherOnePart) {
  FaultCheck c;
  // 20 lost in its own part, 15 and 12 in two others (47 in all): its own part names the fault,
  // though it is under half the loss.
  c.lost = 47;
  c.lost_in_fault = 20;
  c.most_lost_elsewhere = 15;
  EXPECT_TRUE(c.mostInOwnPart());
  c.most_lost_elsewhere = 21;
  EXPECT_FALSE(c.mostInOwnPart());
  // Nothing lost in its own part is never "most", even with nothing lost elsewhere.
  FaultCheck none;
  EXPECT_FALSE(none.mostInOwnPart());
}

TEST(TaskValidation, AnOvercutIntoANeighbourLosesInItsOwnPart) {
  // The expert leaves the neighbour whole (the adjacent deduction is there, at 0); the over-cut
  // loses 10 of its over-cut part and 30 to the neighbour it nicked; the slow hand nicks it too.
  ValidatedAttempt expert, overcut, slow;
  expert.total = 90;
  expert.parts = {{"undercut", 20.0}, {"overcut", 25.0}, {"time", 25.0}, {"adjacent", 0.0}};
  overcut.attempt = Attempt::Overcut;
  overcut.total = 40;
  overcut.parts = {{"undercut", 20.0}, {"overcut", 15.0}, {"time", 25.0}, {"adjacent", -30.0}};
  slow.attempt = Attempt::Slow;
  slow.total = 40;
  slow.parts = {{"undercut", 20.0}, {"overcut", 25.0}, {"time", 5.0}, {"adjacent", -30.0}};
  const FaultCheck c = compareWithExpert(expert, overcut, TaskKind::Cavity, 70);
  EXPECT_DOUBLE_EQ(c.lost, 40.0);
  EXPECT_DOUBLE_EQ(c.lost_in_fault, 40.0);  // the over-cut's 10 and the neighbour's 30
  EXPECT_DOUBLE_EQ(c.most_lost_elsewhere, 0.0);
  EXPECT_TRUE(c.mostInOwnPart());
  // A slow hand's fault is time: the neighbour it nicked is another fault, and the larger one.
  const FaultCheck s = compareWithExpert(expert, slow, TaskKind::Cavity, 70);
  EXPECT_DOUBLE_EQ(s.lost_in_fault, 20.0);
  EXPECT_DOUBLE_EQ(s.most_lost_elsewhere, 30.0);
  EXPECT_FALSE(s.mostInOwnPart());
  EXPECT_EQ(s.most_lost_part, "adjacent");
}

// The built-in class I on the molar at level 7, its second hand and two faults: the times come from
// the professional drilled here, the token and the under-cut fail, and the JSON says so.
TEST(TaskValidation, TheClassOneCavityAtLevelSevenSeparatesItsAttempts) {
  auto task = builtinTask("class1_cavity");
  ASSERT_TRUE(task.ok()) << task.message();
  auto molar = builtinMolarTooth(7);
  ASSERT_TRUE(molar.ok());
  test::TempDir dir;
  ValidationSettings s;
  s.attempts = {Attempt::Token, Attempt::Undercut};
  s.work_dir = dir.path().string();
  s.time_from_professional = true;
  auto v = validateTask(*task, *molar, s);
  ASSERT_TRUE(v.ok()) << v.message();
  EXPECT_TRUE(v->valid()) << (v->failures.empty() ? "" : v->failures.front());
  ASSERT_EQ(v->attempts.size(), 3u);
  EXPECT_EQ(v->professional, "the built-in path class1_cavity, recorded");
  EXPECT_TRUE(v->timed_here);
  EXPECT_NEAR(v->task.target_s, 1.25 * v->professional_s, 1e-9);
  const ValidatedAttempt& expert = v->attempts[0];
  EXPECT_GE(expert.total, 85.0);
  EXPECT_LT(expert.total, 100.0);  // a second hand, not the ideal itself
  ASSERT_TRUE(expert.agreement_percent.has_value());
  EXPECT_GT(*expert.agreement_percent, 90.0);
  EXPECT_LT(v->attempts[1].total, 20.0);   // token
  EXPECT_LT(v->attempts[2].total, 70.0);   // under-cut
  ASSERT_EQ(v->faults.size(), 2u);
  EXPECT_EQ(v->faults[0].most_lost_part, "undercut");
  const auto j = validationJson(*v);
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["attempts"].size(), 3u);
  EXPECT_EQ(j["attempts"][1]["attempt"], "token");
  EXPECT_TRUE(j["attempts"][1]["parts"].contains("undercut"));
  EXPECT_EQ(j["checks"][0]["own_parts"], nlohmann::ordered_json::array({"undercut"}));
  // No session is left behind.
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(TaskValidation, ATasksTextCannotBreakTheTableOrReachTheTerminalRaw) {
  TaskValidation v;
  v.task.name = "t";
  v.task.title = "Class I \x1b[2J| new\nline";
  v.professional = "the ideal session a\x07.dses";
  const std::string md = validationMarkdown(v);
  EXPECT_EQ(md.find('\x1b'), std::string::npos) << md;
  EXPECT_EQ(md.find('\x07'), std::string::npos) << md;
  EXPECT_NE(md.find("Class I \\x1B[2J\\| new\\x0Aline"), std::string::npos) << md;
  EXPECT_NE(md.find("a\\x07.dses"), std::string::npos) << md;
}

TEST(TaskValidation, AVolumeIdealIsAnErrorThatSaysHowToSetASession) {
  Task task;
  task.name = "t";
  task.kind = TaskKind::Cavity;
  task.ideal = idealVolumeFile("ideal.dvol");
  auto molar = builtinMolarTooth(5);
  ASSERT_TRUE(molar.ok());
  test::TempDir dir;
  ValidationSettings s;
  s.work_dir = dir.path().string();
  auto v = validateTask(task, *molar, s);
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.message().find("task set-ideal"), std::string::npos) << v.message();
}

}  // namespace
}  // namespace dentsim
