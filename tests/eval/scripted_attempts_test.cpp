// The scripted attempts drilled and scored end to end on a small carious block: the careful removal takes the caries and little else and scores high; the trench and the wide box score low, each losing in its own part.
#include <gtest/gtest.h>

#include <numbers>

#include "eval/cut_score.h"
#include "eval_fixtures.h"
#include "io/session_file.h"
#include "sim/novice_paths.h"
#include "sim/session_run.h"
#include "test_support.h"

namespace dentsim {
namespace {

// A 128^3 grid of 0.05 mm voxels (a level-9 molar's voxel is 0.04 mm): enamel over dentin (z 0..4
// mm, the enamel from 3 mm), and an ellipsoid lesion 1.6 x 1.0 x 0.8 mm whose top lies 0.6 mm under
// the surface.
ToothVolume cariousBlock() {
  ToothVolume t{VolumeFrame::axisAligned(7, 0.05, {0, 0, 0}), BrickVolume(7)};
  test::setBox(t, {0, 0, 0}, {128, 128, 60}, makeVoxel(Material::Dentin));
  test::setBox(t, {0, 0, 60}, {128, 128, 80}, makeVoxel(Material::Enamel));
  // An ellipsoid lesion, 1.6 x 1.0 x 0.8 mm, centred 1 mm under the surface.
  for (uint32_t z = 52; z < 68; ++z)
    for (uint32_t y = 54; y < 74; ++y)
      for (uint32_t x = 48; x < 80; ++x) {
        const double u = (x + 0.5 - 64.0) / 16.0, v = (y + 0.5 - 64.0) / 10.0, w = (z + 0.5 - 60.0) / 8.0;
        if (u * u + v * v + w * w <= 1.0) t.voxels.setVoxel(x, y, z, makeVoxel(Material::Caries));
      }
  return t;
}

struct Scored {
  SessionScore score;
  ToothVolume tooth;
};

// Drills the attempt, records it, reads the session back and scores it like any student's. The bur
// cuts four times as fast as by default, and the paths are paced for it, so that the test is short
// under the sanitizers too.
Scored drillAndScore(const ToothVolume& initial, Attempt attempt, const Task& task) {
  test::TempDir dir;
  SimParams params = defaultSimParams();
  params.cutting.removal_rate_mm3_per_s *= 4.0;
  auto path = cariesAttemptPath(attempt, initial.voxels, initial.frame, params, task.drill_tool);
  EXPECT_TRUE(path.ok()) << path.message();
  Scored out{{}, initial};
  ScriptedSessionOptions so;
  so.drill_tool = task.drill_tool;
  auto run = recordScriptedSession(out.tooth, params, *path, dir.file("s.dses"), SessionInfo{}, so);
  EXPECT_TRUE(run.ok()) << run.message();
  EXPECT_EQ(run->steps_lost, 0u);
  auto session = readSessionFile(dir.file("s.dses"));
  EXPECT_TRUE(session.ok()) << session.message();
  auto score = scoreCut(task, initial, out.tooth, nullptr, &*session, scoreFiles("block", attemptName(attempt), "s.dses"));
  EXPECT_TRUE(score.ok()) << score.message();
  out.score = std::move(*score);
  return out;
}

Task blockTask() {
  Task t = test::cariesTask();
  t.drill_tool = "round_bur_010";
  return t;
}

TEST(ScriptedAttempts, TheCarefulRemovalTakesTheCariesAndLittleHealthyTissue) {
  const ToothVolume initial = cariousBlock();
  const Scored expert = drillAndScore(initial, Attempt::Expert, blockTask());
  const nlohmann::ordered_json& r = expert.score.report;
  const double caries = r["volumes"]["caries"]["initial_mm3"].get<double>();
  EXPECT_NEAR(caries, 4.0 / 3.0 * std::numbers::pi * 0.8 * 0.5 * 0.4, 0.01);  // the ellipsoid's volume
  EXPECT_GE(r["volumes"]["caries"]["removed_mm3"].get<double>(), 0.9 * caries) << r.dump(1);
  // Healthy tissue outside the zone: under a tenth of the lesion; in all, no more than the tissue
  // over the lesion (its 1.6 x 1.0 mm outline, 0.6 mm deep at most: under 0.96 mm^3) and its leeway.
  EXPECT_LE(r["zones"]["healthy_outside_zone_mm3"].get<double>(), 0.1 * caries) << r.dump(1);
  EXPECT_LE(r["volumes"]["healthy"]["removed_mm3"].get<double>(), 1.6) << r.dump(1);
  EXPECT_FALSE(r["pulp_exposed"].get<bool>());
  EXPECT_GE(expert.score.total, 90.0) << expert.score.summary;
  EXPECT_TRUE(expert.score.warnings.empty());
}

TEST(ScriptedAttempts, TheTrenchAndTheWideBoxScoreFarBelowTheExpert) {
  const ToothVolume initial = cariousBlock();
  const Task task = blockTask();
  const Scored expert = drillAndScore(initial, Attempt::Expert, task);
  const Scored trench = drillAndScore(initial, Attempt::Trench, task);
  const Scored box = drillAndScore(initial, Attempt::Overcut, task);
  // The trench removes no caries: no removal points, no time points, and its healthy cut costs.
  EXPECT_EQ(trench.score.report["components"]["removal"]["points"].get<double>(), 0.0);
  EXPECT_GT(trench.score.report["deductions"]["healthy"]["points"].get<double>(), 0.0);
  EXPECT_LT(trench.score.total, 40.0) << trench.score.summary;
  // The box removes the caries too, but it pays for the healthy tissue around it.
  EXPECT_GT(box.score.report["components"]["removal"]["points"].get<double>(), 45.0) << box.score.summary;
  EXPECT_GT(box.score.report["deductions"]["healthy"]["points"].get<double>(), 20.0) << box.score.summary;
  EXPECT_GE(expert.score.total - trench.score.total, 20.0);
  EXPECT_GE(expert.score.total - box.score.total, 20.0);
}

}  // namespace
}  // namespace dentsim
