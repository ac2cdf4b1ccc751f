// Tests of the score benchmark: a short run of task validate's attempts on a carious block gives the same scores to the last bit twice, with its times from the professional, and its table and chart.
#include "bench/score_bench.h"

#include <gtest/gtest.h>

#include "eval/cut_score.h"
#include "test_support.h"

namespace dentsim::bench {
namespace {

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
  ValidationSettings s;
  s.attempts = {Attempt::Trench};
  s.work_dir = dir.path().string();
  auto first = runScoreBench(block, {*caries}, s);
  ASSERT_TRUE(first.ok()) << first.message();
  auto second = runScoreBench(block, {*caries}, s);
  ASSERT_TRUE(second.ok()) << second.message();
  ASSERT_EQ(first->tasks.size(), 1u);
  const TaskValidation& v = first->tasks[0];
  ASSERT_EQ(v.attempts.size(), 2u);
  EXPECT_EQ(v.attempts[0].attempt, Attempt::Expert);
  EXPECT_EQ(v.attempts[1].attempt, Attempt::Trench);
  EXPECT_EQ(scoreBenchJson(*first).dump(), scoreBenchJson(*second).dump());
  // The block is not the task's level-9 molar: the times come from the professional drilled here,
  // the target 1.25 times its session, no time points left at 3 times it.
  EXPECT_TRUE(v.timed_here);
  EXPECT_EQ(v.task.name, "caries_removal");
  EXPECT_NEAR(v.task.target_s, 1.25 * v.professional_s, 1e-9);
  EXPECT_NEAR(v.task.failure_s, 3.0 * v.professional_s, 1e-9);
  // The second careful hand scores high, the trench low; the table and chart name both.
  EXPECT_GE(v.attempts[0].total, 85.0);
  EXPECT_LT(v.attempts[1].total, 40.0);
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
