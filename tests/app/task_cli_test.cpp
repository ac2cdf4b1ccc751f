// Tests of the teacher's workflow on a tooth of their own: voxelize stands a sideways tooth up, info prints its frame, and `dentsim task new|check` write and check a task on it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "io/stl_file.h"
#include "test_meshes.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::runDentsim;
using test::TempDir;
using test::writeBytes;

// A tooth lying on its side, crown toward -y: a dentin bar 4 x 14 x 4 mm with a caries pocket near
// the crown end, and an enamel cap over that end.
class TaskCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeBytes(dir_.file("dentin.stl"), encodeStlBinary(test::box({-2, -5, -2}, {2, 9, 2}), "dentin"));
    writeBytes(dir_.file("enamel.stl"), encodeStlBinary(test::box({-2.5, -7, -2.5}, {2.5, -4, 2.5}), "enamel"));
    writeBytes(dir_.file("caries.stl"), encodeStlBinary(test::box({-0.5, -7, -0.5}, {0.5, -5.5, 0.5}), "caries"));
    const auto v = runDentsim("voxelize --cpu --enamel " + dir_.file("enamel.stl") + " --dentin " + dir_.file("dentin.stl") +
                              " --caries " + dir_.file("caries.stl") + " --level 6 -o " + dir_.file("t.dvol"));
    voxelized_ = v.output;
    ASSERT_EQ(v.exit_code, 0) << v.output;
  }
  nlohmann::json info() const {
    const auto r = runDentsim("info --json " + dir_.file("t.dvol"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(r.output.substr(r.output.find('{')));
  }
  TempDir dir_;
  std::string voxelized_;
};

TEST_F(TaskCli, VoxelizeFindsTheCrownAndStandsTheToothUp) {
  EXPECT_NE(voxelized_.find("crown axis found from the enamel"), std::string::npos) << voxelized_;
  EXPECT_NE(voxelized_.find("after quarter turns that stand the crown up"), std::string::npos) << voxelized_;
  const nlohmann::json j = info();
  const auto& frame = j["tooth_frame"];
  EXPECT_EQ(frame["crown_from"], "found");
  EXPECT_GT(frame["crown"][2].get<double>(), 0.99);
  // The source's -y (the crown) is now +z: z = source -y.
  EXPECT_EQ(frame["turn"][7].get<int>(), -1);
  // The enamel cap is on top: its bounds reach the tooth's top, 3 mm of cap above 14 mm of dentin
  // (the bars' lengths along y become heights).
  const auto& enamel = j["bounds"]["enamel"], &dentin = j["bounds"]["dentin"], &tooth = j["bounds"]["tooth"];
  EXPECT_DOUBLE_EQ(enamel["hi_mm"][2].get<double>(), tooth["hi_mm"][2].get<double>());
  EXPECT_GT(enamel["lo_mm"][2].get<double>(), dentin["lo_mm"][2].get<double>() + 10.0);
  EXPECT_NEAR(tooth["hi_mm"][2].get<double>() - tooth["lo_mm"][2].get<double>(), 16.0, 0.5);
  // The occlusal centre sits on the top of the cap, in the middle across it.
  EXPECT_NEAR(frame["occlusal_centre_mm"][2].get<double>(), tooth["hi_mm"][2].get<double>(), 0.3);
  const auto r = runDentsim("info " + dir_.file("t.dvol"));
  EXPECT_NE(r.output.find("crown     (0.00"), std::string::npos) << r.output;  // (0.001, 0.000, 1.000): the box's voxels
  EXPECT_NE(r.output.find(", 1.000)  found\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("turned    x = source +x, y = source +z, z = source -y"), std::string::npos) << r.output;
}

TEST_F(TaskCli, AGivenCrownAxisWinsAndKeepOrientationTurnsNothing) {
  const auto given = runDentsim("voxelize --cpu --enamel " + dir_.file("enamel.stl") + " --dentin " + dir_.file("dentin.stl") +
                                " --level 6 --crown-axis 0,1,0 -o " + dir_.file("g.dvol"));
  ASSERT_EQ(given.exit_code, 0) << given.output;
  EXPECT_NE(given.output.find("crown axis given"), std::string::npos) << given.output;
  const auto kept = runDentsim("voxelize --cpu --enamel " + dir_.file("enamel.stl") + " --dentin " + dir_.file("dentin.stl") +
                               " --level 6 --keep-orientation -o " + dir_.file("k.dvol"));
  ASSERT_EQ(kept.exit_code, 0) << kept.output;
  EXPECT_NE(kept.output.find("crown axis found from the enamel, now (0.001, -1.000, 0.001); mesial"), std::string::npos)
      << kept.output;  // still toward -y, not turned
  EXPECT_EQ(kept.output.find("quarter turns"), std::string::npos) << kept.output;
  const auto bad = runDentsim("voxelize --cpu --enamel " + dir_.file("enamel.stl") + " --level 6 --mesial-axis 0,-2,0 "
                              "--crown-axis 0,-1,0 -o " + dir_.file("b.dvol"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("--mesial-axis: lies along the crown axis"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.file("b.dvol")));
}

TEST_F(TaskCli, TaskNewWritesATaskThatChecksAndRefusesWhatCannotWork) {
  const std::string task = dir_.file("course/t_caries.json");
  std::filesystem::create_directories(dir_.file("course"));
  const auto made = runDentsim("task new --tooth " + dir_.file("t.dvol") + " --kind caries --title \"Side caries\" -o " + task);
  ASSERT_EQ(made.exit_code, 0) << made.output;
  std::ifstream in(task);
  const nlohmann::json j = nlohmann::json::parse(in);
  // A task names only files in its own folder: the tooth from the folder above is copied beside it.
  EXPECT_EQ(j["tooth"], "t.dvol");
  EXPECT_EQ(test::readBytes(dir_.file("course/t.dvol")), test::readBytes(dir_.file("t.dvol")));
  EXPECT_NE(made.output.find("copied " + dir_.file("t.dvol") + " beside the task"), std::string::npos) << made.output;
  EXPECT_EQ(j["title"], "Side caries");
  EXPECT_EQ(j["insertion_axis"], nlohmann::json::array({0, 0, 1}));
  EXPECT_EQ(j["tools"]["drill"], "round_bur_010");
  const auto checked = runDentsim("task check " + task);
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_NE(checked.output.find(": ok: caries task \"Side caries\""), std::string::npos) << checked.output;

  // Not over itself, not over another file, not access without a pulp.
  EXPECT_EQ(runDentsim("task new --tooth " + dir_.file("t.dvol") + " --kind caries -o " + task).exit_code, 1);
  const auto access = runDentsim("task new --tooth " + dir_.file("t.dvol") + " --kind access -o " + dir_.file("a.json"));
  EXPECT_EQ(access.exit_code, 1);
  EXPECT_NE(access.output.find("no pulp in this tooth"), std::string::npos) << access.output;
  EXPECT_EQ(runDentsim("task new --tooth " + dir_.file("t.dvol") + " --kind caries -o " + dir_.file("t.dvol")).exit_code, 1);
  EXPECT_TRUE(std::filesystem::exists(dir_.file("t.dvol")));
}

TEST_F(TaskCli, TaskCheckNamesEveryProblem) {
  const std::string task = dir_.file("bad.json");
  std::ofstream(task) << R"({"format": "dentsim-task", "version": 2, "name": "bad", "kind": "caries", "tooth": "none.dvol",)"
                         R"( "tools": {"drill": "mirror_size4", "mirror": "round_bur_010"}, "target_s": 60, "failure_s": 120,)"
                         R"( "force_error_n": 3})";
  const auto r = runDentsim("task check " + task);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("error: tools.drill: \"mirror_size4\" is not a bur"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: tools.mirror: \"round_bur_010\" is not a mirror"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: tooth: "), std::string::npos) << r.output;
  // The roots-pointing axis on the real tooth.
  std::ofstream(task) << R"({"format": "dentsim-task", "version": 2, "name": "bad", "kind": "caries", "tooth": "t.dvol",)"
                         R"( "tools": {"drill": "round_bur_010"}, "target_s": 60, "failure_s": 120, "force_error_n": 3,)"
                         R"( "insertion_axis": [0, 0, -1]})";
  const auto roots = runDentsim("task check " + task);
  EXPECT_EQ(roots.exit_code, 1);
  EXPECT_NE(roots.output.find("insertion_axis: points 180 degrees from the tooth's crown axis"), std::string::npos) << roots.output;
  // A schema error is the parser's one line.
  std::ofstream(task) << R"({"format": "dentsim-task", "version": 2, "name": "bad", "kind": "filling"})";
  const auto schema = runDentsim("task check " + task);
  EXPECT_EQ(schema.exit_code, 1);
  EXPECT_NE(schema.output.find("kind: \"filling\" is not one of"), std::string::npos) << schema.output;
}

}  // namespace
}  // namespace dentsim
