// ToothChoice: which tooth a run starts on (--tooth, --level, the task's), and what the panel's tooth and task pickers change.
#include <gtest/gtest.h>

#include "app/sim_tooth_choice.h"
#include "eval/task_tooth.h"

namespace dentsim::app {
namespace {

TEST(ToothChoice, ABuiltinTaskStartsOnTheMolarAtItsLevel) {
  auto c = ToothChoice::atStart("", 0, kBuiltinMolarTooth, 9);
  ASSERT_TRUE(c) << c.message();
  EXPECT_TRUE(c->builtin());
  EXPECT_EQ(c->level, 9);
  EXPECT_EQ(c->name(), "built-in molar");
}

TEST(ToothChoice, LevelAskedForBuildsTheMolarAtThatLevel) {
  auto c = ToothChoice::atStart("", 7, kBuiltinMolarTooth, 9);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->level, 7);
}

// The molar with its neighbours goes by its session source, and --level rebuilds it at that level.
TEST(ToothChoice, TheNeighboursToothTakesTheLevelAskedFor) {
  auto at_task = ToothChoice::atStart("", 0, "builtin:molar_neighbours", 9);
  ASSERT_TRUE(at_task) << at_task.message();
  EXPECT_EQ(at_task->file, "builtin:molar_neighbours:9");
  auto asked = ToothChoice::atStart("", 7, "builtin:molar_neighbours", 9);
  ASSERT_TRUE(asked) << asked.message();
  EXPECT_EQ(asked->file, "builtin:molar_neighbours:7");
  EXPECT_EQ(asked->level, 7);
}

TEST(ToothChoice, ToothOptionWinsOverTheTasksTooth) {
  auto c = ToothChoice::atStart("my.dvol", 0, "asset:tasks/ct_tooth_3.dvol", 9);
  ASSERT_TRUE(c);
  EXPECT_FALSE(c->builtin());
  EXPECT_EQ(c->file, "my.dvol");
  EXPECT_EQ(c->name(), "my.dvol");
}

TEST(ToothChoice, LevelWithAToothFileIsRefused) {
  EXPECT_FALSE(ToothChoice::atStart("my.dvol", 7, kBuiltinMolarTooth, 9));
  // A task's own file tooth keeps its grid too.
  auto c = ToothChoice::atStart("", 8, "asset:tasks/ct_tooth_3.dvol", 9);
  ASSERT_FALSE(c);
  EXPECT_NE(c.message().find("--level"), std::string::npos);
}

TEST(ToothChoice, ATasksToothComesWithItsLevel) {
  const ToothChoice file = ToothChoice::ofTask("asset:tasks/ct_tooth_3.dvol", 9);
  EXPECT_EQ(file.file, "asset:tasks/ct_tooth_3.dvol");
  const ToothChoice molar = ToothChoice::ofTask(kBuiltinMolarTooth, 8);
  EXPECT_TRUE(molar.builtin());
  EXPECT_EQ(molar.level, 8);
}

TEST(ToothChoice, ThePickerSetsTheLevelOnlyForTheMolar) {
  const ToothChoice molar9{"", 9};
  const ToothChoice file = molar9.picked("course/t.dvol", 6);
  EXPECT_EQ(file.file, "course/t.dvol");
  EXPECT_EQ(file.level, 9);  // kept for when the molar is picked again
  const ToothChoice molar7 = file.picked("", 7);
  EXPECT_TRUE(molar7.builtin());
  EXPECT_EQ(molar7.level, 7);
}

}  // namespace
}  // namespace dentsim::app
