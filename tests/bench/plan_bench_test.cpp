// Tests of the plan benchmark: voxelize's memory estimate holds within 1.5 times of each run's measured peak, on real teeth, for every input path at levels 9 to 12.
#include "bench/plan_bench.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace dentsim::bench {
namespace {

// Every path at levels 9 to 11, and the labels at 12 as well: the level where the bricks, not the
// source, make the peak (2 GB). The other paths' level 12 (2.3 GB and a minute each on the CI
// machine) are in `dentsim bench plan` and docs/PERFORMANCE.md. Time is not asserted here: the
// machine's load decides it (the benchmark reports it against its bound of 2).
TEST(PlanBench, MemoryEstimatesHoldWithinOneAndAHalfOfMeasuredPeaks) {
  const std::filesystem::path data = test::dataDir();
  if (data.empty()) GTEST_SKIP() << "no shared tooth data (../shared/data or DENTSIM_DATA_DIR)";
  test::TempDir dir;
  PlanBenchSettings s;
  s.dentsim = DENTSIM_BINARY;
  s.data_dir = data.string();
  s.scratch = dir.path().string();
  std::vector<PlanRow> rows;
  for (const auto& [paths, levels] : {std::pair{planBenchPaths(), std::vector<int>{9, 10, 11}},
                                      {std::vector<std::string>{"labels"}, std::vector<int>{12}}}) {
    s.paths = paths;
    s.levels = levels;
    auto measured = runPlanBench(s);
    ASSERT_TRUE(measured.ok()) << measured.message();
    rows.insert(rows.end(), measured->begin(), measured->end());
  }
  ASSERT_EQ(rows.size(), 13u);
  for (const PlanRow& r : rows) {
    SCOPED_TRACE(r.path + " level " + std::to_string(r.level));
    EXPECT_GT(r.peak_bytes, uint64_t{50} << 20);  // a real run, not a refusal
    EXPECT_GT(r.planned_seconds, 0.0);
    EXPECT_TRUE(r.memoryWithin()) << "planned " << r.planned_bytes << " B, peak " << r.peak_bytes << " B";
  }
  // The table marks nothing "out" for memory; every row is in the JSON with its ratios.
  const nlohmann::json j = planRowsJson(rows);
  ASSERT_EQ(j["rows"].size(), rows.size());
  for (const auto& row : j["rows"]) EXPECT_TRUE(row["memory_within"].get<bool>()) << row.dump();
}

TEST(PlanBench, AnUnknownPathOrMissingDataIsOneError) {
  test::TempDir dir;
  PlanBenchSettings s;
  s.dentsim = DENTSIM_BINARY;
  s.data_dir = dir.path().string();
  s.scratch = dir.file("scratch");
  auto missing = runPlanBench(s);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("not found (the shared tooth data)"), std::string::npos) << missing.message();
  const std::filesystem::path data = test::dataDir();
  if (data.empty()) GTEST_SKIP() << "no shared tooth data for the unknown path's check";
  s.data_dir = data.string();
  s.paths = {"stl-fpga"};
  auto unknown = runPlanBench(s);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.message(), "stl-fpga: not a plan benchmark path (stl-cpu, stl-gpu, labels, scan)");
}

TEST(PlanBench, RatiosAndBoundsAreBothWays) {
  PlanRow r;
  r.planned_bytes = 150;
  r.peak_bytes = 100;
  r.planned_seconds = 1.0;
  r.seconds = 2.0;
  EXPECT_DOUBLE_EQ(r.memoryRatio(), 1.5);
  EXPECT_TRUE(r.memoryWithin());
  EXPECT_TRUE(r.timeWithin());
  r.planned_bytes = 151;
  EXPECT_FALSE(r.memoryWithin());
  r.planned_bytes = 66;  // 1 / 1.515: too low
  EXPECT_FALSE(r.memoryWithin());
  r.seconds = 2.1;
  EXPECT_FALSE(r.timeWithin());
  EXPECT_NE(planRowsTable({r}).find("(out)"), std::string::npos);
}

}  // namespace
}  // namespace dentsim::bench
