// Two OpenHaptics pens at once against the fake HDAPI: one servo callback for both, each pen's own force and calibration, a fault or unplug on one zeroing both, the stop order, and a two-pen session that replays exactly.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/steady_clock.h"
#include "devices/device_pen.h"
#include "devices/fake_devices.h"
#include "devices/fake_hd/fake_hd_controls.h"
#include "devices/openhaptics_pen.h"
#include "io/session_file.h"
#include "model/tool_generator.h"
#include "sim/haptic_loop.h"
#include "sim/session_recorder.h"
#include "sim/session_run.h"
#include "io/pen_playback.h"
#include "sim/builtin_tooth.h"
#include "sim/scripted_paths.h"
#include "sim/tool_library.h"
#include "test_sessions.h"
#include "test_support.h"
#include "volume/volume_hash.h"

namespace dentsim::devices {
namespace {

using test::FakeHd;
using test::waitFor;

// Two configured pens, "Left" and "Right", as Touch Setup leaves them in $GTDD_HOME/config; the
// drill is Left and the mirror Right throughout.
class OpenHapticsPair : public ::testing::Test {
 protected:
  void SetUp() override {
    if (test::kFakeHdLibrary == nullptr) GTEST_SKIP() << "the fake HDAPI library was not built (DENTSIM_FAKE_HD_LIB unset)";
    std::filesystem::create_directories(home_.path() / "config");
    for (const char* name : {"Left", "Right"})
      std::ofstream(home_.path() / "config" / (std::string(name) + ".config")) << "[fake]\n";
    ::setenv("GTDD_HOME", home_.path().c_str(), 1);
    fake_.load();
    if (HasFatalFailure()) return;
    fake_.reset();  // reads the configuration folder
    options_.library = test::kFakeHdLibrary;
    // A watchdog the test threads cannot trip on a loaded machine, and a short ramp.
    options_.safety.watchdog_ms = 1000;
    options_.safety.ramp_s = 0.02;
  }
  void TearDown() override {
    stopCommanding();
    left_.reset();
    right_.reset();
    fake_.unload();
    ::unsetenv("GTDD_HOME");
  }

  void openBoth() {
    left_ = makeOpenHapticsPen("Left", options_);
    right_ = makeOpenHapticsPen("Right", options_);
    left_->joinSafetyGroup(&hands_, 0);
    right_->joinSafetyGroup(&hands_, 1);
    const Status l = left_->open();
    ASSERT_TRUE(l.ok()) << l.message();
    const Status r = right_->open();
    ASSERT_TRUE(r.ok()) << r.message();
  }
  void enableBoth() {
    ASSERT_TRUE(left_->enable().ok());
    ASSERT_TRUE(right_->enable().ok());
  }

  // A stand-in haptic loop: commands each pen its own force every 0.5 ms until stopped.
  void startCommanding(const Vec3& left_force, const Vec3& right_force) {
    commanding_.store(true);
    commander_ = std::thread([this, left_force, right_force] {
      while (commanding_.load()) {
        const int64_t now = steadyNowNs();
        if (left_) left_->command(Wrench{left_force, {}}, now);
        if (right_) right_->command(Wrench{right_force, {}}, now);
        std::this_thread::sleep_for(std::chrono::microseconds(500));
      }
    });
  }
  void stopCommanding() {
    commanding_.store(false);
    if (commander_.joinable()) commander_.join();
  }
  Vec3 sentTo(const char* pen) {
    fake_.select(pen);
    return fake_.force();
  }
  // Both pens' motors at these forces, once the ramp is through.
  void expectPushing(const Vec3& left_force, const Vec3& right_force) {
    EXPECT_TRUE(waitFor([&] { return sentTo("Left") == left_force && sentTo("Right") == right_force; }))
        << "Left got " << sentTo("Left").z << " N, Right " << sentTo("Right").z << " N";
  }
  void expectNoBreaches() {
    for (const char* pen : {"Left", "Right"}) {
      fake_.select(pen);
      const FakeHd::Breaches b = fake_.breachCounts();
      EXPECT_EQ(b.control_calls_while_running, 0) << pen;
      EXPECT_EQ(b.sent_after_stop, 0) << pen;
      EXPECT_EQ(b.stopped_pushing, 0) << pen;
    }
  }

  dentsim::test::TempDir home_;
  FakeHd fake_;
  OpenHapticsOptions options_;
  SafetyGroup hands_;
  std::unique_ptr<HapticDevice> left_, right_;
  std::atomic<bool> commanding_{false};
  std::thread commander_;
};

TEST_F(OpenHapticsPair, DevicesListsEveryConfiguredPenByName) {
  const auto entries = enumerateOpenHaptics(options_);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].name, "openhaptics:Left");
  EXPECT_EQ(entries[1].name, "openhaptics:Right");
  for (const auto& e : entries) {
    EXPECT_EQ(e.state, DeviceState::Ready) << e.name << ": " << e.reason;
    EXPECT_EQ(e.model, "Touch");
  }
  // Each was probed on its own: the fake numbers its pens' serials in configuration order.
  EXPECT_NE(entries[0].location.find("serial FAKE-0001"), std::string::npos) << entries[0].location;
  EXPECT_NE(entries[1].location.find("serial FAKE-0002"), std::string::npos) << entries[1].location;
  // The probe let them go again.
  for (const char* pen : {"Left", "Right"}) {
    fake_.select(pen);
    EXPECT_EQ(fake_.deviceInitialized(), 0) << pen;
  }
}

TEST_F(OpenHapticsPair, OneServoCallbackServesBothAndEachPenGetsItsOwnForce) {
  openBoth();
  EXPECT_EQ(fake_.scheduledCallbacks(), 1);
  EXPECT_EQ(fake_.schedulerRunning(), 1);
  EXPECT_EQ(left_->state(), DeviceState::Ready);
  EXPECT_EQ(right_->state(), DeviceState::Ready);
  // Each pen reads its own device.
  fake_.select("Left");
  fake_.setPosition({-10, 0, 0});
  fake_.select("Right");
  fake_.setPosition({20, 5, 0});
  DeviceReading l, r;
  ASSERT_TRUE(waitFor([&] {
    return left_->read(0, &l) && right_->read(0, &r) && l.pose.position.x == -10 && r.pose.position.x == 20;
  }));
  EXPECT_EQ(r.pose.position.y, 5);
  // And gets its own force: the drill pushes down 0.3 N, the mirror sideways 0.2 N.
  enableBoth();
  startCommanding({0, 0, -0.3}, {0.2, 0, 0});
  expectPushing({0, 0, -0.3}, {0.2, 0, 0});
  // Both advance: one callback, one frame each per pass.
  for (const char* pen : {"Left", "Right"}) {
    fake_.select(pen);
    const long frames = fake_.frames();
    EXPECT_TRUE(waitFor([&] { return fake_.frames() >= frames + 3; })) << pen;
  }
  stopCommanding();
  left_->close();
  right_->close();
  EXPECT_EQ(fake_.schedulerRunning(), 0);
  EXPECT_EQ(fake_.scheduledCallbacks(), 0);
  expectNoBreaches();
}

// The mirror pen's HD error: it is zero in the frame that failed, the drill pen is zero no later
// than the same scheduler pass (it comes first in the pass, so at worst it sent its force in that
// pass before the mirror's frame failed), and the group says the mirror failed first.
TEST_F(OpenHapticsPair, AnErrorOnTheMirrorPenZeroesBothWithinOneServoTick) {
  openBoth();
  enableBoth();
  startCommanding({0, 0, -0.3}, {0.2, 0, 0});
  expectPushing({0, 0, -0.3}, {0.2, 0, 0});
  fake_.select("Right");
  fake_.injectError(test::kHdCommError, 7);
  ASSERT_TRUE(waitFor([&] { return right_->state() == DeviceState::Fault; }));
  EXPECT_NE(right_->reason().find("communication error"), std::string::npos) << right_->reason();
  long right_last_force = 0, right_error = 0, left_last_force = 0, unused = 0;
  fake_.ticks(&right_last_force, &right_error);
  ASSERT_GE(right_error, 0);
  EXPECT_LT(right_last_force, right_error) << "the failing frame itself sent zero";
  // Wait a few passes to see that the drill stays at zero while commands keep coming.
  const long passes = fake_.ticks(nullptr, nullptr);
  ASSERT_TRUE(waitFor([&] { return fake_.ticks(nullptr, nullptr) >= passes + 5; }));
  fake_.select("Left");
  fake_.ticks(&left_last_force, &unused);
  EXPECT_LE(left_last_force, right_error) << "the drill pushed after the pass in which the mirror failed";
  EXPECT_EQ(sentTo("Left"), Vec3{});
  EXPECT_EQ(sentTo("Right"), Vec3{});
  EXPECT_TRUE(hands_.halted());
  EXPECT_EQ(hands_.firstFault(), 1);
  EXPECT_EQ(left_->safety().faulted(), false) << "the drill did nothing wrong: it is held, not faulted";
  stopCommanding();
  left_->close();
  right_->close();
  expectNoBreaches();
}

TEST_F(OpenHapticsPair, UnpluggingOnePenFaultsItZeroesBothAndItComesBackOnlyWhenPluggedIn) {
  openBoth();
  enableBoth();
  startCommanding({0, 0, -0.3}, {0.2, 0, 0});
  expectPushing({0, 0, -0.3}, {0.2, 0, 0});
  fake_.select("Left");
  fake_.setPlugged(0);
  ASSERT_TRUE(waitFor([&] { return left_->state() == DeviceState::Fault; }));
  EXPECT_TRUE(waitFor([&] { return sentTo("Right") == Vec3{}; })) << "the mirror keeps pushing without the drill";
  EXPECT_EQ(hands_.firstFault(), 0);
  // The mirror pen still tracks: its servo frames go on.
  fake_.select("Right");
  const long frames = fake_.frames();
  EXPECT_TRUE(waitFor([&] { return fake_.frames() > frames + 3; }));
  // Reopening the drill while unplugged fails and says why; after plugging in it opens again.
  const Status again = left_->open();
  EXPECT_FALSE(again.ok());
  EXPECT_EQ(left_->state(), DeviceState::Disconnected);
  EXPECT_NE(again.message().find("hdInitDevice(\"Left\")"), std::string::npos) << again.message();
  fake_.select("Left");
  fake_.setPlugged(1);
  const Status back = left_->open();
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(left_->state(), DeviceState::Ready);
  // A new segment clears the group: both push again.
  hands_.clear();
  right_->disable();
  enableBoth();
  expectPushing({0, 0, -0.3}, {0.2, 0, 0});
  stopCommanding();
  left_->close();
  right_->close();
  expectNoBreaches();
}

TEST_F(OpenHapticsPair, EachPenHasItsOwnCalibration) {
  fake_.select("Left");
  fake_.setCalibration(test::kHdCalibrationOk, test::kHdCalibrationAuto);
  fake_.select("Right");
  fake_.setCalibration(test::kHdCalibrationNeedsManualInput, test::kHdCalibrationInkwell);
  openBoth();
  EXPECT_EQ(left_->state(), DeviceState::Ready);
  EXPECT_EQ(right_->state(), DeviceState::NeedsHoming);
  EXPECT_NE(right_->reason().find("inkwell"), std::string::npos) << right_->reason();
  EXPECT_FALSE(right_->enable().ok());
  // Only the mirror pen is asked to update, and it becomes ready by itself once it needs only that.
  fake_.select("Right");
  fake_.setCalibration(test::kHdCalibrationNeedsUpdate, test::kHdCalibrationInkwell);
  ASSERT_TRUE(waitFor([&] {
    right_->service();
    return right_->state() == DeviceState::Ready;
  }));
  unsigned style = 0;
  EXPECT_GE(fake_.calibrationUpdates(&style), 1);
  EXPECT_EQ(style, unsigned(test::kHdCalibrationInkwell));
  fake_.select("Left");
  EXPECT_EQ(fake_.calibrationUpdates(nullptr), 0);
  left_->close();
  right_->close();
  expectNoBreaches();
}

// Closing one pen while the other pushes: the closed one ends on a zero frame and is let go, the
// other is served on (after a short pause at zero); closing the second stops the scheduler with
// both motors at zero. In either order, and nothing is sent after the stop.
TEST_F(OpenHapticsPair, StopOrderEitherPenFirstLeavesNoForceAfterTheStop) {
  for (const char* first : {"Left", "Right"}) {
    SCOPED_TRACE(first);
    fake_.reset();
    hands_.clear();
    openBoth();
    enableBoth();
    startCommanding({0, 0, -0.3}, {0.2, 0, 0});
    expectPushing({0, 0, -0.3}, {0.2, 0, 0});
    const bool left_first = std::string(first) == "Left";
    std::unique_ptr<HapticDevice>& closing = left_first ? left_ : right_;
    closing->close();
    EXPECT_EQ(sentTo(first), Vec3{});
    fake_.select(first);
    EXPECT_EQ(fake_.deviceInitialized(), 0);
    EXPECT_EQ(fake_.schedulerRunning(), 1) << "the other pen is still served";
    const char* other = left_first ? "Right" : "Left";
    const Vec3 other_force = left_first ? Vec3{0.2, 0, 0} : Vec3{0, 0, -0.3};
    EXPECT_TRUE(waitFor([&] { return sentTo(other) == other_force; })) << "the other pen pushes again after the pause";
    stopCommanding();
    (left_first ? right_ : left_)->close();
    EXPECT_EQ(fake_.schedulerRunning(), 0);
    EXPECT_EQ(fake_.scheduledCallbacks(), 0);
    EXPECT_EQ(sentTo("Left"), Vec3{});
    EXPECT_EQ(sentTo("Right"), Vec3{});
    expectNoBreaches();
    left_.reset();
    right_.reset();
  }
}

// The scene: a drill and a mirror pen on two OpenHaptics devices, under the real haptic
// loop and session recorder. The hands follow the built-in cavity preparation on the molar (the
// devices' millimetres are the tooth's); the session replays to the same voxels. Then the mirror
// pen's device fails: both pens are at zero within one servo pass while the loop runs on, and the
// failure is in the file.
TEST_F(OpenHapticsPair, ATwoPenSessionRecordsAndReplaysToTheSameVolumeAndAMirrorFaultZeroesBoth) {
  auto built = builtinMolarTooth(6);
  ASSERT_TRUE(built.ok()) << built.message();
  ToothVolume tooth = std::move(*built);
  const ToothVolume start = tooth;
  CavityPathSettings cavity;
  cavity.laps = 0.2;
  auto path = cavityPreparationPath(tooth.voxels, tooth.frame, cavity);
  ASSERT_TRUE(path.ok()) << path.message();
  ScriptedPen drill_hand(path->path, PenRole::Drill), mirror_hand(path->path, PenRole::Mirror);
  const SimParams params = defaultSimParams();
  auto drill_tool = loadToolModel(kDefaultBur, params.point_shell);
  auto mirror_tool = loadToolModel(kDefaultMirror, params.point_shell);
  ASSERT_TRUE(drill_tool.ok() && mirror_tool.ok());
  openBoth();
  test::FakePedal pedal;  // the foot pedal, full on
  ASSERT_TRUE(pedal.open().ok());
  pedal.press(1.0);
  const DeviceMapping same;  // device millimetres are the tooth's
  DevicePen drill(*left_, same, &pedal), mirror(*right_, same);
  // Each step: both hands where the path has them at that time (the mirror held still where the
  // path has no mirror), then a loop step and about a servo frame's pause.
  PenReading mirror_rest;
  const bool path_has_mirror = mirror_hand.read(0.0, &mirror_rest);
  if (!path_has_mirror) {
    // Well above the tooth's grid, out of everyone's way.
    const double top = double(tooth.frame.dim()) * tooth.frame.voxel_mm;
    mirror_rest.grip.position = {tooth.frame.origin_mm[0], tooth.frame.origin_mm[1], tooth.frame.origin_mm[2] + top + 20};
  }
  const auto move = [&](double t) {
    PenReading r;
    if (drill_hand.read(t, &r)) {
      fake_.select("Left");
      fake_.setGrip(r.grip, r.velocity);
    }
    fake_.select("Right");
    if (path_has_mirror && mirror_hand.read(t, &r)) fake_.setGrip(r.grip, r.velocity);
    else fake_.setGrip(mirror_rest.grip);
  };
  dentsim::test::TempDir dir;
  const std::string file = dir.file("two_pens.dses");
  const int steps = int(drill_hand.endTime() * 1000.0);
  ASSERT_GT(steps, 200);
  {
    HapticLoop loop(tooth.voxels, tooth.frame, params, *drill_tool, &*mirror_tool, nullptr);
    loop.attach(PenRole::Drill, &drill);
    loop.attach(PenRole::Mirror, &mirror);
    move(0.0);
    PenReading first;
    // The first servo frames after the move: each proxy starts on its pen's first reading.
    const long frames = fake_.frames();
    ASSERT_TRUE(waitFor([&] { return fake_.frames() >= frames + 2; }));
    ASSERT_TRUE(waitFor([&] { return drill.read(0.0, &first); }));
    loop.placeTool(PenRole::Drill, first.grip);
    ASSERT_TRUE(waitFor([&] { return mirror.read(0.0, &first); }));
    loop.placeTool(PenRole::Mirror, first.grip);
    const SessionInfo info =
        sessionHeader(dentsim::test::sessionInfo("2026-11-27T10:00:00Z"), start, params, kDefaultBur, kDefaultMirror);
    SessionRecorder recorder;
    ASSERT_TRUE(recorder.start(loop, file, info).ok());
    enableBoth();
    bool drill_pushed = false;
    for (int k = 0; k < steps; ++k) {
      move(k * 0.001);
      loop.step();
      std::this_thread::sleep_for(std::chrono::microseconds(100));
      drill_pushed = drill_pushed || norm(sentTo("Left")) > 0.05;
    }
    EXPECT_TRUE(drill_pushed) << "the drill never pushed back: the test proves nothing";
    EXPECT_NE(volumeHashHex(tooth.voxels, tooth.frame), volumeHashHex(start.voxels, start.frame))
        << "the drill never cut: the test proves nothing";

    // The mirror pen's device fails while the loop runs on.
    fake_.select("Right");
    fake_.injectError(test::kHdCommError, 7);
    for (int k = 0; k < 4000 && right_->state() != DeviceState::Fault; ++k) {
      loop.step();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    ASSERT_EQ(right_->state(), DeviceState::Fault);
    recorder.noteDevice(PenRole::Mirror, stateName(right_->state()), right_->reason());
    const long passes = fake_.ticks(nullptr, nullptr);
    for (int k = 0; k < 20; ++k) {
      loop.step();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    ASSERT_TRUE(waitFor([&] { return fake_.ticks(nullptr, nullptr) >= passes + 5; }));
    long right_last = 0, right_error = 0, left_last = 0, unused = 0;
    fake_.select("Right");
    fake_.ticks(&right_last, &right_error);
    fake_.select("Left");
    fake_.ticks(&left_last, &unused);
    EXPECT_LT(right_last, right_error);
    EXPECT_LE(left_last, right_error) << "the drill pushed after the pass in which the mirror failed";
    EXPECT_EQ(sentTo("Left"), Vec3{});
    ASSERT_TRUE(recorder.finish(SessionEnd{loop.stepsRun(), volumeHashHex(tooth.voxels, tooth.frame), "stopped"}).ok());
    left_->close();
    right_->close();
  }
  expectNoBreaches();
  EXPECT_EQ(fake_.schedulerRunning(), 0);

  // The file: both pens at every step, the mirror's failure noted, and an exact replay.
  auto session = readSessionFile(file);
  ASSERT_TRUE(session.ok()) << session.message();
  ASSERT_GE(session->steps.size(), size_t(steps));
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(session->steps[k].hasReading(0)) << k;
    ASSERT_TRUE(session->steps[k].hasReading(1)) << k;
  }
  ASSERT_EQ(session->devices.size(), 1u);
  EXPECT_EQ(session->devices[0].pen, 1);
  EXPECT_EQ(session->devices[0].state, "fault");
  EXPECT_GE(session->devices[0].step, uint64_t(steps));
  ToothVolume replayed_tooth = start;
  auto replayed = replaySession(*session, replayed_tooth, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  EXPECT_EQ(replayed->steps, session->steps.size());
  EXPECT_EQ(replayed->final_hash, session->end->final_hash);
  EXPECT_TRUE(replayed->recorded_hash_matches);
  EXPECT_EQ(replayed->force_mismatches, 0u);
  EXPECT_TRUE(replayed_tooth.voxels == tooth.voxels);
}

}  // namespace
}  // namespace dentsim::devices
