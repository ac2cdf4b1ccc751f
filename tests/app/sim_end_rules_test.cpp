// EndRules: when the simulator's run quits by itself (the loop time given, the bench's frames, the script's end, its last frame and linger), checked frame by frame without a window.
#include <gtest/gtest.h>

#include "app/sim_end_rules.h"

namespace dentsim::app {
namespace {

TEST(EndRules, ExitAfterStopsAtItsLoopTimeWithAReason) {
  SimEndOptions o;
  o.exit_after_s = 2.0;
  EndRules rules(o, false, std::nullopt);
  rules.limits(1.9, 10);
  EXPECT_FALSE(rules.quit());
  // 60 frames at 30 frames/s land a hair under 2.0 in floating point: still the end.
  rules.limits(60 / 30.0 - 1e-12, 11);
  EXPECT_TRUE(rules.quit());
  EXPECT_EQ(rules.reason(), "--exit-after ended the run");
}

TEST(EndRules, BenchStopsAfterItsFramesWithoutBlamingTheScore) {
  SimEndOptions o;
  o.bench_frames = 5;
  o.bench_from_s = 1.0;
  EndRules rules(o, true, 10.0);
  EXPECT_FALSE(rules.benchDraws(0.5));
  EXPECT_TRUE(rules.benchDraws(1.0));
  EXPECT_EQ(rules.warmUpFramesLeftOut(), 3);
  rules.limits(1.2, 4);
  EXPECT_FALSE(rules.quit());
  rules.limits(1.3, 5);
  EXPECT_TRUE(rules.quit());
  EXPECT_TRUE(rules.reason().empty());
}

TEST(EndRules, TheScriptEndsOnceItHasSettledAndOnlyWhileItsSegmentRuns) {
  EndRules rules({}, true, 3.0);
  EXPECT_FALSE(rules.scriptEnds(3.1, true));  // the last cut's edits are still on their way
  EXPECT_TRUE(rules.scriptEnds(3.2, true));
  EXPECT_FALSE(rules.scriptEnds(3.2, false));  // stopped already (the panel's Stop)
  EndRules no_script({}, true, std::nullopt);
  EXPECT_FALSE(no_script.scriptEnds(100.0, true));
}

TEST(EndRules, HeadlessQuitsWhenTheLastShotIsWritten) {
  EndRules rules({}, true, 3.0);
  rules.scriptEnded(5.0);
  rules.afterScript(true, false, 5.0);
  EXPECT_FALSE(rules.quit());  // the end's picture is not written yet
  rules.afterScript(false, false, 5.1);
  EXPECT_TRUE(rules.quit());
  EXPECT_TRUE(rules.reason().empty());
}

TEST(EndRules, HeadlessWithALoopTimeGivenRunsOnPastTheScript) {
  SimEndOptions o;
  o.exit_after_s = 10.0;
  EndRules rules(o, true, 3.0);
  rules.scriptEnded(5.0);
  rules.afterScript(false, false, 6.0);
  EXPECT_FALSE(rules.quit());
}

TEST(EndRules, AWindowStaysUnlessAskedToQuitAtTheEnd) {
  EndRules stays({}, false, 3.0);
  stays.scriptEnded(5.0);
  stays.afterScript(false, false, 500.0);
  EXPECT_FALSE(stays.quit());

  SimEndOptions o;
  o.exit_at_end = true;
  EndRules quits(o, false, 3.0);
  quits.scriptEnded(5.0);
  quits.afterScript(false, false, 5.0);
  EXPECT_TRUE(quits.quit());
}

TEST(EndRules, TheLingerCountsWallTimeFromTheScriptsEnd) {
  SimEndOptions o;
  o.linger_s = 4.0;
  EndRules rules(o, false, 3.0);
  rules.afterScript(false, false, 100.0);
  EXPECT_FALSE(rules.quit());  // the script has not ended: nothing to linger after
  rules.scriptEnded(10.0);
  rules.afterScript(false, false, 13.9);
  EXPECT_FALSE(rules.quit());
  rules.afterScript(false, true, 14.0);
  EXPECT_FALSE(rules.quit());  // a new segment runs: the student drills on
  rules.afterScript(false, false, 14.0);
  EXPECT_TRUE(rules.quit());
}

TEST(EndRules, FullDetailQuitsOnlyABenchmarkThatAsksForIt) {
  EndRules plain({}, false, std::nullopt);
  plain.fullDetailReached();
  EXPECT_FALSE(plain.quit());
  SimEndOptions o;
  o.quit_at_full_detail = true;
  EndRules bench(o, false, std::nullopt);
  bench.fullDetailReached();
  EXPECT_TRUE(bench.quit());
}

TEST(EndRules, AStopKeepsItsReasonForTheScoreNotMade) {
  EndRules rules({}, false, std::nullopt);
  rules.stopQuietly();
  EXPECT_TRUE(rules.quit());
  EXPECT_TRUE(rules.reason().empty());
  rules.stop("the window was closed");
  EXPECT_EQ(rules.reason(), "the window was closed");
}

}  // namespace
}  // namespace dentsim::app
