// Tests of the tooth a task or a session starts from: the task's own tooth file (named relative to the task), the built-in molar at the task's level or another, and a session's built-in source.
#include "eval/task_tooth.h"

#include <gtest/gtest.h>

#include <fstream>

#include "eval/cut_score.h"
#include "eval_fixtures.h"
#include "test_support.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

using test::setBox;

// A task file beside a tooth file, naming it relatively; the rest is the built-in caries task's.
std::string writeTaskNamingTooth(const test::TempDir& dir, const std::string& tooth) {
  const std::string path = dir.file("my_task.json");
  std::ofstream(path) << R"({"format":"dentsim-task","version":2,"name":"my_task","kind":"caries",)"
                         R"("tooth":")" << tooth << R"(","level":7,"tools":{"drill":"round_bur_010","mirror":"mirror_size2"},)"
                         R"("target_s":300,"failure_s":900,"force_error_n":3})";
  return path;
}

TEST(TaskTooth, ATaskFileNamesItsToothRelativeToItsOwnFolder) {
  test::TempDir dir;
  ToothVolume t = test::emptyTooth();
  setBox(t, {2, 2, 2}, {10, 10, 6}, makeVoxel(Material::Dentin));
  setBox(t, {2, 2, 6}, {10, 10, 8}, makeVoxel(Material::Enamel));
  ASSERT_TRUE(saveTooth(dir.file("mine.dvol"), t).ok());
  auto task = builtinTask(writeTaskNamingTooth(dir, "mine.dvol"));
  ASSERT_TRUE(task.ok()) << task.message();
  EXPECT_EQ(task->tooth, dir.file("mine.dvol"));
  EXPECT_EQ(task->level, 7);
  EXPECT_EQ(task->mirror_tool, "mirror_size2");
  // A file's grid is its own: the level asked for does not apply to it.
  for (int level : {0, 9}) {
    auto loaded = taskTooth(*task, level);
    ASSERT_TRUE(loaded.ok()) << loaded.message();
    EXPECT_EQ(volumeHash(loaded->voxels, loaded->frame), volumeHash(t.voxels, t.frame));
  }
}

TEST(TaskTooth, AMissingToothFileIsAnErrorNamingIt) {
  test::TempDir dir;
  auto task = builtinTask(writeTaskNamingTooth(dir, "gone.dvol"));
  ASSERT_TRUE(task.ok()) << task.message();
  auto loaded = taskTooth(*task, 0);
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.message().find(dir.file("gone.dvol")), std::string::npos) << loaded.message();
}

// A task from elsewhere cannot make dentsim open a file outside its folder: an absolute tooth or one
// that climbs out is refused when the task is read, naming the field and never reading the file.
TEST(TaskTooth, AToothOutsideTheTasksFolderIsRefused) {
  test::TempDir dir;
  for (const char* outside : {"/etc/passwd", "../../../../etc/passwd", "teeth/../../x.dvol"}) {
    auto task = builtinTask(writeTaskNamingTooth(dir, outside));
    ASSERT_FALSE(task.ok()) << outside;
    EXPECT_NE(task.message().find(dir.file("my_task.json") + ": tooth names \"" + outside + "\""), std::string::npos)
        << task.message();
    EXPECT_EQ(task.message().find("root:"), std::string::npos) << task.message();
  }
}

TEST(TaskTooth, TheBuiltinMolarAtTheTasksLevelOrTheOneAskedFor) {
  auto task = builtinTask("caries");
  ASSERT_TRUE(task.ok()) << task.message();
  ASSERT_EQ(task->tooth, kBuiltinMolarTooth);
  task->level = 6;
  auto own = taskTooth(*task, 0);
  ASSERT_TRUE(own.ok()) << own.message();
  EXPECT_EQ(own->frame.level, 6);
  auto asked = taskTooth(*task, 7);
  ASSERT_TRUE(asked.ok()) << asked.message();
  EXPECT_EQ(asked->frame.level, 7);
}

TEST(TaskTooth, ASessionsBuiltinSourceRebuildsTheMolarAndABadOneIsAnError) {
  EXPECT_EQ(builtinToothSource(7), "builtin:molar:7");
  SessionRecording session;
  session.info.tooth_source = builtinToothSource(6);
  auto rebuilt = resolveSessionTooth(session, "/nowhere/s.dses", "");
  ASSERT_TRUE(rebuilt.ok()) << rebuilt.message();
  EXPECT_EQ(rebuilt->frame.level, 6);
  for (const char* bad : {"builtin:molar:", "builtin:molar:x7", "builtin:molar:123", "a scan"}) {
    session.info.tooth_source = bad;
    auto r = resolveSessionTooth(session, "/nowhere/s.dses", "");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find("/nowhere/s.dses"), std::string::npos) << r.message();
  }
}

}  // namespace
}  // namespace dentsim
