// Tests for src/eval/task_ideal.cpp and the identity checks of idealForTask: an ideal recorded on one tooth is not scored against another, and a changed file is named.
#include "eval/task_ideal.h"

#include <gtest/gtest.h>

#include <fstream>

#include "eval/cut_score.h"
#include "eval_fixtures.h"
#include "io/file_hash.h"
#include "test_support.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

struct Fixture {
  test::TempDir dir;
  ToothVolume initial = test::enamelSlab();
  ToothVolume ideal = test::enamelSlab();
  Task task = test::cavityTask();
  Fixture() {
    test::setBox(ideal, {4, 4, 4}, {12, 12, 8}, makeVoxel(Material::Empty));
    EXPECT_TRUE(saveTooth(dir.file("ideal.dvol"), ideal).ok());
    task.ideal = idealVolumeFile(dir.file("ideal.dvol"));
    task.ideal->initial_hash = volumeHashHex(initial.voxels, initial.frame);
    task.ideal->final_hash = volumeHashHex(ideal.voxels, ideal.frame);
  }
};

TEST(TaskIdeal, TheRecordedIdentityLetsTheIdealThrough) {
  Fixture f;
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, f.initial, &warnings);
  ASSERT_TRUE(made.ok()) << made.message();
  EXPECT_TRUE(made->voxels == f.ideal.voxels);
}

TEST(TaskIdeal, AnotherToothIsNamedNotScored) {
  Fixture f;
  ToothVolume other = f.initial;
  other.voxels.setVoxel(0, 0, 0, makeVoxel(Material::Dentin));  // one voxel differs
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, other, &warnings);
  ASSERT_FALSE(made.ok());
  EXPECT_NE(made.message().find("ideal: recorded on another tooth (hash " + f.task.ideal->initial_hash + ")"), std::string::npos)
      << made.message();
  EXPECT_NE(made.message().find("dentsim task set-ideal"), std::string::npos) << made.message();
}

TEST(TaskIdeal, AChangedIdealFileIsNamed) {
  Fixture f;
  ToothVolume changed = f.ideal;
  changed.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Empty));
  ASSERT_TRUE(saveTooth(f.dir.file("ideal.dvol"), changed).ok());
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, f.initial, &warnings);
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.message().rfind(f.dir.file("ideal.dvol") + ": the professional's final tooth changed since", 0), 0u)
      << made.message();
}

TEST(TaskIdeal, AChangedSessionFileIsNamed) {
  test::TempDir dir;
  std::ofstream(dir.file("p.dses")) << "not really a session";
  auto hash = fileHash(dir.file("p.dses"));
  ASSERT_TRUE(hash.ok());
  IdealSpec spec;
  spec.kind = IdealKind::Session;
  spec.path = dir.file("p.dses");
  spec.session_hash = hashHex(*hash);
  const ToothVolume tooth = test::enamelSlab();
  EXPECT_TRUE(checkIdealIdentity(spec, tooth, "task t: ideal").ok());
  std::ofstream(dir.file("p.dses")) << "not really a session, edited";
  const Status st = checkIdealIdentity(spec, tooth, "task t: ideal");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind(dir.file("p.dses") + ": the professional's session changed since it was recorded", 0), 0u)
      << st.message();
}

TEST(TaskIdeal, SetIdealRefusesWhatItCannotUse) {
  test::TempDir dir;
  std::ofstream(dir.file("v1.json")) << R"({"format": "dentsim-task", "version": 1, "name": "c", "kind": "caries",)"
                                        R"( "tooth": "builtin:molar", "tools": {"drill": "round_bur_010"}, "target_s": 300,)"
                                        R"( "failure_s": 900, "force_error_n": 3})";
  std::ofstream(dir.file("s.dses")) << "x";
  auto v1 = setTaskIdeal(dir.file("v1.json"), dir.file("s.dses"), "");
  ASSERT_FALSE(v1.ok());
  EXPECT_EQ(v1.message(), dir.file("v1.json") + ": a version 1 task file: set-ideal writes version 2 only (docs/SCORING.md, section 10)");
  std::ofstream(dir.file("v2.json")) << R"({"format": "dentsim-task", "version": 2, "name": "c", "kind": "caries",)"
                                        R"( "tooth": "builtin:molar", "tools": {"drill": "round_bur_010"}, "target_s": 300,)"
                                        R"( "failure_s": 900, "force_error_n": 3})";
  auto bad_session = setTaskIdeal(dir.file("v2.json"), dir.file("s.dses"), "");
  ASSERT_FALSE(bad_session.ok());
  EXPECT_EQ(bad_session.message().rfind(dir.file("s.dses") + ": ", 0), 0u) << bad_session.message();
  // The task file is untouched by a refusal.
  std::ifstream in(dir.file("v2.json"));
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text.find("ideal"), std::string::npos);
}

}  // namespace
}  // namespace dentsim
