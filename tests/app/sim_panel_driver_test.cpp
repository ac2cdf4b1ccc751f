// drivePanel: the panel's asks carried out on a fake simulator, in the order that keeps each session to one tool and one starting tooth.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/sim_panel_driver.h"

namespace dentsim::app {
namespace {

// Logs every call; a segment runs or not as the calls leave it.
class FakeSimulator : public PanelTarget {
 public:
  std::vector<std::string> calls;
  bool running = true;
  bool bur_differs = true;
  bool builtin = true;
  std::string fail_on;  // a call that returns an error

  Status applyParams() override { return log("params"); }
  void applyNormalMode() override { (void)log("normals"); }
  void applyPedal() override { (void)log("pedal"); }
  Status teacherFolder() override { return Ok{}; }
  Status pickTask() override {
    running = true;  // a new task restarts on its tooth
    return log("task");
  }
  Status pickTooth() override {
    running = true;
    return log("tooth");
  }
  Status recordIdeal() override {
    running = false;  // recording ends the segment
    return log("ideal");
  }
  bool segmentRunning() const override { return running; }
  Status endSegment(const std::string& reason) override {
    running = false;
    return log("end:" + reason);
  }
  Status startSegment() override {
    running = true;
    return log("start");
  }
  bool burDiffers() const override { return bur_differs; }
  Status changeBur() override { return log("bur"); }
  bool builtinTooth() const override { return builtin; }
  void keepFileLevel() override { (void)log("keep level"); }
  Status rebuildTooth(bool new_level) override { return log(new_level ? "rebuild level" : "rebuild"); }
  Status scoreNow() override { return log("score"); }

 private:
  Status log(const std::string& call) {
    calls.push_back(call);
    if (call == fail_on) return Error{"failed: " + call};
    return Ok{};
  }
};

using Calls = std::vector<std::string>;

TEST(PanelDriver, NothingAskedCallsNothing) {
  FakeSimulator sim;
  ASSERT_TRUE(drivePanel({}, sim));
  EXPECT_TRUE(sim.calls.empty());
}

TEST(PanelDriver, ANewBurEndsTheSegmentAndStartsANewOne) {
  FakeSimulator sim;
  PanelAsks a;
  a.bur_changed = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"end:bur changed", "bur", "start"}));
}

TEST(PanelDriver, TheBurInUseOrAStoppedSegmentNeedsNoNewSegment) {
  FakeSimulator same;
  same.bur_differs = false;
  PanelAsks a;
  a.bur_changed = true;
  ASSERT_TRUE(drivePanel(a, same));
  EXPECT_TRUE(same.calls.empty());
  FakeSimulator stopped;
  stopped.running = false;
  ASSERT_TRUE(drivePanel(a, stopped));
  EXPECT_EQ(stopped.calls, (Calls{"bur"}));
}

TEST(PanelDriver, ATaskPickedWinsOverAToothPickedInTheSameFrame) {
  FakeSimulator sim;
  PanelAsks a;
  a.task_changed = true;
  a.tooth_changed = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"task"}));
}

TEST(PanelDriver, ResetRebuildsTheUncutToothInANewSegment) {
  FakeSimulator sim;
  PanelAsks a;
  a.reset = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"end:reset", "rebuild", "start"}));
}

TEST(PanelDriver, ALevelRebuildsOnlyTheMolar) {
  PanelAsks a;
  a.level_changed = true;
  FakeSimulator molar;
  ASSERT_TRUE(drivePanel(a, molar));
  EXPECT_EQ(molar.calls, (Calls{"end:reset", "rebuild level", "start"}));
  FakeSimulator file;
  file.builtin = false;
  ASSERT_TRUE(drivePanel(a, file));
  EXPECT_EQ(file.calls, (Calls{"keep level"}));
}

TEST(PanelDriver, ScoreAfterRecordAsIdealDoesNotEndTheSegmentTwice) {
  FakeSimulator sim;
  PanelAsks a;
  a.record_ideal = true;
  a.score = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"ideal", "score"}));
}

TEST(PanelDriver, StopThenStartInOneFrameOnlyStops) {
  // Whether a segment runs is read once before the buttons, so both together leave it stopped.
  FakeSimulator sim;
  PanelAsks a;
  a.stop = true;
  a.start = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"end:stopped"}));
}

TEST(PanelDriver, ParametersComeBeforeAnyRestart) {
  FakeSimulator sim;
  PanelAsks a;
  a.params_changed = true;
  a.normal_mode_changed = true;
  a.speed_changed = true;
  a.reset = true;
  ASSERT_TRUE(drivePanel(a, sim));
  EXPECT_EQ(sim.calls, (Calls{"params", "normals", "pedal", "end:reset", "rebuild", "start"}));
}

TEST(PanelDriver, TheFirstErrorEndsIt) {
  FakeSimulator sim;
  sim.fail_on = "bur";
  PanelAsks a;
  a.bur_changed = true;
  a.score = true;
  const Status st = drivePanel(a, sim);
  ASSERT_FALSE(st);
  EXPECT_EQ(st.message(), "failed: bur");
  EXPECT_EQ(sim.calls, (Calls{"end:bur changed", "bur"}));
}

}  // namespace
}  // namespace dentsim::app
