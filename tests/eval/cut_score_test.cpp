// Tests of scoring end to end: the report names the ideal whatever its source, an empty ideal is an error for either kind, and the picture's red follows the task's kind.
#include "eval/cut_score.h"

#include <gtest/gtest.h>

#include "eval/task_kinds.h"
#include "eval_fixtures.h"
#include "test_support.h"
#include "volume/tooth_file.h"

namespace dentsim {
namespace {

using test::setBox;

constexpr Voxel kEmpty = 0;

// Enamel over dentin (the crown faces +z) with 8 caries voxels in the enamel's top layer.
ToothVolume tooth() {
  ToothVolume t = test::emptyTooth();
  setBox(t, {0, 0, 0}, {16, 16, 6}, makeVoxel(Material::Dentin));
  setBox(t, {0, 0, 6}, {16, 16, 8}, makeVoxel(Material::Enamel));
  setBox(t, {4, 4, 7}, {8, 6, 8}, makeVoxel(Material::Caries));
  return t;
}

TEST(CutScore, TheReportNamesTheIdealWhateverItsSource) {
  test::TempDir dir;
  const ToothVolume initial = tooth();
  ToothVolume ideal = initial;
  setBox(ideal, {4, 4, 6}, {8, 6, 8}, kEmpty);
  ASSERT_TRUE(saveTooth(dir.file("prof.dvol"), ideal).ok());
  Task task = test::cariesTask();
  task.ideal = idealVolumeFile(dir.file("prof.dvol"));
  // From the task: made here, and named with its kind and path.
  auto from_task = scoreCut(task, initial, ideal, nullptr, nullptr, scoreFiles("a.dvol", "b.dvol", ""));
  ASSERT_TRUE(from_task.ok()) << from_task.message();
  EXPECT_EQ(from_task->report["inputs"]["ideal"]["kind"], "volume");
  EXPECT_EQ(from_task->report["inputs"]["ideal"]["path"], dir.file("prof.dvol"));
  EXPECT_EQ(from_task->report["inputs"]["ideal"]["from"], "task");
  EXPECT_EQ(from_task->report["zones"]["target"], "ideal cavity");
  ASSERT_TRUE(from_task->ideal.has_value());
  // Given on the command line instead.
  ScoreFiles files = scoreFiles("a.dvol", "b.dvol", "");
  files.ideal = "given.dvol";
  auto given = scoreCut(task, initial, ideal, &ideal, nullptr, files);
  ASSERT_TRUE(given.ok()) << given.message();
  EXPECT_EQ(given->report["inputs"]["ideal"]["path"], "given.dvol");
  EXPECT_EQ(given->report["inputs"]["ideal"]["from"], "command line");
  EXPECT_FALSE(given->ideal.has_value());
  // None: a caries task measures against its caries, and says so.
  task.ideal.reset();
  auto none = scoreCut(task, initial, ideal, nullptr, nullptr, scoreFiles("a.dvol", "b.dvol", ""));
  ASSERT_TRUE(none.ok()) << none.message();
  EXPECT_TRUE(none->report["inputs"]["ideal"].is_null());
  EXPECT_EQ(none->report["zones"]["target"], "caries and its access along the insertion axis");
}

TEST(CutScore, AnEmptyIdealIsAnErrorForEitherKind) {
  const ToothVolume initial = tooth();
  ScoreFiles files = scoreFiles("a.dvol", "b.dvol", "");
  files.ideal = "same.dvol";
  for (Task task : {test::cariesTask(), test::cavityTask()}) {
    auto s = scoreCut(task, initial, initial, &initial, nullptr, files);
    ASSERT_FALSE(s.ok()) << taskKindName(task.kind);
    EXPECT_EQ(s.message(), "same.dvol: the ideal cavity is empty: the ideal tooth removed nothing from the initial one");
  }
}

TEST(CutScore, WarningsReachTheReportAndTheCaller) {
  const ToothVolume initial = tooth();
  ToothVolume ideal = initial, student = initial;
  setBox(ideal, {4, 4, 6}, {8, 6, 8}, kEmpty);
  setBox(student, {12, 12, 7}, {14, 14, 8}, kEmpty);
  Task task = test::cavityTask();
  task.ideal = idealVolumeFile("unused");
  auto s = scoreCut(task, initial, student, &ideal, nullptr, scoreFiles("start.dvol", "b.dvol", ""));
  ASSERT_TRUE(s.ok()) << s.message();
  ASSERT_EQ(s->warnings.size(), 1u);
  EXPECT_NE(s->warnings[0].find("task test_cavity on start.dvol: the cut does not overlap the ideal cavity"), std::string::npos)
      << s->warnings[0];
  EXPECT_EQ(s->report["warnings"].size(), 1u);
  EXPECT_EQ(s->total, 0.0);
  EXPECT_EQ(s->total_max, 50.0);
}

// A kind's name stands for the built-in task its row names (eval/task_kinds.h), so "caries" and
// "caries_removal" load the same task; access has no such task and its name is no task's.
TEST(CutScore, AKindsNameLoadsTheBuiltInTaskItsRowNames) {
  for (const TaskKindRow& row : kTaskKindTable) {
    EXPECT_EQ(isBuiltinTaskName(row.name), row.builtin_task != nullptr) << row.name;
    if (!row.builtin_task) continue;
    auto short_name = builtinTask(row.name), full_name = builtinTask(row.builtin_task);
    ASSERT_TRUE(short_name.ok()) << short_name.message();
    ASSERT_TRUE(full_name.ok()) << full_name.message();
    EXPECT_EQ(short_name->name, full_name->name);
    EXPECT_EQ(short_name->kind, row.kind);
  }
  EXPECT_EQ(kindTaskNames(), "caries, cavity, crown");
}

}  // namespace
}  // namespace dentsim
