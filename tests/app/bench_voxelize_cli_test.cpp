// Test of `dentsim bench voxelize`: a small run through the binary writes a JSON row per level and share.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace dentsim {
namespace {

using test::NoLeakCheckForGpuChild;

TEST(BenchVoxelizeCliTest, SmallRunWritesEveryRow) {
  test::TempDir dir;
  const NoLeakCheckForGpuChild no_leak_check;
  const test::CommandResult r =
      test::runDentsim("bench voxelize --levels 6 --fractions 25,100 --repeat 1 --out " + dir.path().string());
  if (r.exit_code != 0 && r.output.find("no Vulkan device") != std::string::npos)
    GTEST_SKIP() << "no Vulkan device: " << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("OpenVDB / dentsim"), std::string::npos) << r.output;  // the table on stdout
  for (const char* name : {"voxelize.json", "voxelize.md", "voxelize.svg"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir.path() / name)) << name;

  std::ifstream in(dir.path() / "voxelize.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["settings"]["repeats"], 1);
  const nlohmann::json& rows = j["rows"];
  ASSERT_EQ(rows.size(), 2u);  // one level x two shares, level-major in the order given
  EXPECT_EQ(rows[0]["level"], 6);
  EXPECT_EQ(rows[0]["fraction"], 0.25);
  EXPECT_EQ(rows[1]["fraction"], 1.0);
  // A quarter of the triangles is fewer triangles (within the decimator's 5% slack of 25%).
  const double quarter = rows[0]["triangles"], full = rows[1]["triangles"];
  EXPECT_LT(quarter, full);
  EXPECT_LT(quarter, 0.3 * full);
  EXPECT_EQ(rows[0]["voxel_mm"], rows[1]["voxel_mm"]);  // one grid per level
  for (const nlohmann::json& row : rows) {
    EXPECT_GT(row["dentsim"]["ms"].get<double>(), 0.0);
    EXPECT_EQ(row["dentsim"]["runs_ms"].size(), 1u);
    EXPECT_EQ(row["tissues"].size(), 4u);
    if (row["openvdb"]["available"].get<bool>()) {
      EXPECT_GT(row["openvdb"]["ms"].get<double>(), 0.0);
      EXPECT_GT(row["ratio_openvdb_over_dentsim"].get<double>(), 0.0);
    } else {
      EXPECT_FALSE(row["openvdb"]["name"].get<std::string>().empty());  // says why it is absent
      EXPECT_EQ(row["ratio_openvdb_over_dentsim"].get<double>(), 0.0);
    }
  }
}

TEST(BenchVoxelizeCliTest, RejectsAShareAboveAll) {
  test::TempDir dir;
  const test::CommandResult r = test::runDentsim("bench voxelize --fractions 150 --out " + dir.path().string());
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "voxelize.json"));
}

}  // namespace
}  // namespace dentsim
