// Tests of the score benchmark: the gap and part checks on scores counted by hand, and a short run on a carious block that gives the same scores to the last bit twice.
#include "bench/score_bench.h"

#include <gtest/gtest.h>

#include "eval/cut_score.h"
#include "test_support.h"

namespace dentsim::bench {
namespace {

AttemptScore made(const std::string& task, Attempt a, std::vector<std::pair<std::string, double>> parts) {
  AttemptScore s;
  s.task = task;
  s.kind = TaskKind::Caries;
  s.attempt = a;
  s.parts = std::move(parts);
  for (const auto& [name, points] : s.parts) s.total += points;
  s.total = std::max(0.0, s.total);
  return s;
}

TEST(ScoreBench, ChecksFindTheGapAndThePartThatLostIt) {
  ScoreBenchResult r;
  r.scores.push_back(made("caries", Attempt::Expert, {{"removal", 49}, {"time", 25}, {"force", 25}, {"healthy", -1}}));
  // Lost 30 in time only: a gap of 30, all of it in the fault's part.
  r.scores.push_back(made("caries", Attempt::Slow, {{"removal", 49}, {"time", 0}, {"force", 20}, {"healthy", -1}}));
  // Lost 10 in force and 15 in removal: a gap of 25 but not mostly in force.
  r.scores.push_back(made("caries", Attempt::Heavy, {{"removal", 34}, {"time", 25}, {"force", 15}, {"healthy", -1}}));
  // A gain elsewhere does not hide a loss: 12 lost in the healthy part, 2 gained in removal.
  r.scores.push_back(made("caries", Attempt::Overcut, {{"removal", 50}, {"time", 25}, {"force", 25}, {"healthy", -12}}));
  const std::vector<NoviceCheck> c = checkNovices(r);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].attempt, Attempt::Slow);
  EXPECT_DOUBLE_EQ(c[0].gap, 30.0);
  EXPECT_DOUBLE_EQ(c[0].lost, 30.0);
  EXPECT_DOUBLE_EQ(c[0].lost_in_fault, 25.0);
  EXPECT_TRUE(c[0].gap_ok);
  EXPECT_TRUE(c[0].part_ok);
  EXPECT_DOUBLE_EQ(c[1].gap, 25.0);
  EXPECT_DOUBLE_EQ(c[1].lost_in_fault, 10.0);
  EXPECT_FALSE(c[1].part_ok);
  EXPECT_DOUBLE_EQ(c[2].gap, 10.0);
  EXPECT_DOUBLE_EQ(c[2].lost, 11.0);
  EXPECT_FALSE(c[2].gap_ok);
  EXPECT_TRUE(c[2].part_ok);
}

TEST(ScoreBench, FaultPartsPerTask) {
  EXPECT_EQ(faultParts(TaskKind::Caries, Attempt::Overcut), std::vector<std::string>{"healthy"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Overcut), std::vector<std::string>{"overcut"});
  EXPECT_EQ(faultParts(TaskKind::Cavity, Attempt::Undercut), std::vector<std::string>{"undercut"});
  EXPECT_EQ(faultParts(TaskKind::Access, Attempt::Undercut), (std::vector<std::string>{"undercut", "pulp cap"}));
  EXPECT_EQ(faultParts(TaskKind::Access, Attempt::Overcut), std::vector<std::string>{"overcut"});
  EXPECT_EQ(faultParts(TaskKind::Caries, Attempt::Heavy), std::vector<std::string>{"force"});
  EXPECT_TRUE(faultParts(TaskKind::Caries, Attempt::Expert).empty());
}

// Enamel over dentin with an ellipsoid lesion 1.6 x 1.0 x 0.8 mm under the surface (0.05 mm voxels).
ToothVolume cariousBlock() {
  ToothVolume t{VolumeFrame::axisAligned(7, 0.05, {0, 0, 0}), BrickVolume(7)};
  for (uint32_t z = 0; z < 80; ++z)
    for (uint32_t y = 0; y < 128; ++y)
      for (uint32_t x = 0; x < 128; ++x) {
        const double u = (x + 0.5 - 64.0) / 16.0, v = (y + 0.5 - 64.0) / 10.0, w = (z + 0.5 - 60.0) / 8.0;
        const Material m = u * u + v * v + w * w <= 1.0 ? Material::Caries : (z < 60 ? Material::Dentin : Material::Enamel);
        t.voxels.setVoxel(x, y, z, makeVoxel(m));
      }
  return t;
}

TEST(ScoreBench, RepeatedRunsGiveTheSameScoresToTheLastBit) {
  const ToothVolume block = cariousBlock();
  auto caries = builtinTask("caries");
  ASSERT_TRUE(caries.ok()) << caries.message();
  test::TempDir dir;
  ScoreBenchSettings s;
  s.attempts = {Attempt::Trench};
  s.work_dir = dir.path().string();
  auto first = runScoreBench(block, {*caries}, s);
  ASSERT_TRUE(first.ok()) << first.message();
  auto second = runScoreBench(block, {*caries}, s);
  ASSERT_TRUE(second.ok()) << second.message();
  ASSERT_EQ(first->scores.size(), 2u);
  EXPECT_EQ(first->scores[0].attempt, Attempt::Expert);
  EXPECT_EQ(first->scores[1].attempt, Attempt::Trench);
  EXPECT_EQ(scoreBenchJson(*first).dump(), scoreBenchJson(*second).dump());
  // The task's times come from the expert: the target 1.25 times its time, no points left at 3 times.
  ASSERT_EQ(first->tasks.size(), 1u);
  EXPECT_EQ(first->scores[0].task, "caries_removal");
  EXPECT_DOUBLE_EQ(first->tasks[0].target_s, 1.25 * first->scores[0].elapsed_s);
  EXPECT_DOUBLE_EQ(first->tasks[0].failure_s, 3.0 * first->scores[0].elapsed_s);
  // The expert scores high, the trench low; the table and chart name both.
  EXPECT_GE(first->scores[0].total, 90.0);
  EXPECT_LT(first->scores[1].total, 40.0);
  const std::string md = scoreBenchMarkdown(*first);
  EXPECT_NE(md.find("| expert |"), std::string::npos) << md;
  EXPECT_NE(md.find("| trench | wrong place: a trench |"), std::string::npos) << md;
  const std::string svg = scoreBenchSvg(*first);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("trench"), std::string::npos);
  // No session is left behind.
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace dentsim::bench
