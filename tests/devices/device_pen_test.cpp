// DevicePen: the device-to-tooth mapping against hand-worked values, the pedal merged, and a pen unplugged and replugged mid-session under the real haptic loop and recorder.
#include "devices/device_pen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/steady_clock.h"
#include "devices/fake_devices.h"
#include "io/session_file.h"
#include "sim/haptic_loop.h"
#include "sim/session_recorder.h"
#include "sim/sim_fixtures.h"
#include "test_sessions.h"
#include "test_support.h"
#include "volume/volume_hash.h"

namespace dentsim::devices {
namespace {

void expectNear(const Vec3& got, const Vec3& want, double tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// The fake's 100 mm workspace mapped to a 10 mm reach around (5, 5, 5), turned 90 degrees about z.
DeviceMapping quarterTurn(const DeviceSpec& spec) {
  const Quat axes = Quat::fromAxisAngle({0, 0, 1}, std::numbers::pi / 2);
  Pose grip;
  grip.position = {5, 5, 5};
  grip.rotation = Quat::fromAxisAngle({1, 0, 0}, 0.3);
  return mapWorkspace(spec, grip, 10.0, axes);
}

TEST(DevicePen, MapsTheWorkspaceOntoTheToothByHand) {
  test::FakePen fake;
  ASSERT_TRUE(fake.open().ok());
  const DeviceMapping m = quarterTurn(fake.spec());
  EXPECT_DOUBLE_EQ(m.scale, 0.1);  // 10 mm of reach over the 100 mm side
  DevicePen pen(fake, m);
  // Device +x 10 mm at 100 mm/s: world +y (the quarter turn) 1 mm at 10 mm/s, from the centre (5, 5, 5).
  fake.setGrip({10, 0, 0}, {100, 0, 0});
  PenReading r;
  ASSERT_TRUE(pen.read(0.0, &r));
  expectNear(r.grip.position, {5, 6, 5}, 1e-12);
  expectNear(r.velocity, {0, 10, 0}, 1e-12);
  // A 3-DOF pen senses no rotation: the tool keeps the rotation it was mapped with.
  EXPECT_EQ(r.grip.rotation, Quat::fromAxisAngle({1, 0, 0}, 0.3));
  EXPECT_EQ(r.angular_velocity, Vec3{});
  fake.setGrip({0, -20, 30});
  ASSERT_TRUE(pen.read(0.001, &r));
  expectNear(r.grip.position, {5 + 2, 5, 5 + 3}, 1e-12);  // device -y -> world +x; z stays z
}

TEST(DevicePen, ForcesGoBackIntoTheDeviceFrameUnscaled) {
  test::FakePen fake;
  ASSERT_TRUE(fake.open().ok());
  ASSERT_TRUE(fake.enable().ok());
  DevicePen pen(fake, quarterTurn(fake.spec()));
  // World +y 0.3 N is device +x 0.3 N (the inverse quarter turn), not scaled by the workspace.
  pen.display(Wrench{{0, 0.3, 0}, {}}, 0.0);
  const SafetyLayer::Output o = fake.sendToMotors(steadyNowNs());
  ASSERT_EQ(o.gate, SafetyGate::Pass) << gateName(o.gate);
  expectNear(o.wrench.force, {0.3, 0, 0}, 1e-12);
}

TEST(DevicePen, ThePedalDeviceSetsTheTurbineAndAPulledPedalStopsIt) {
  test::FakePen fake;
  test::FakePedal pedal;
  ASSERT_TRUE(fake.open().ok());
  ASSERT_TRUE(pedal.open().ok());
  DevicePen pen(fake, quarterTurn(fake.spec()), &pedal);
  pedal.press(0.7);
  PenReading r;
  ASSERT_TRUE(pen.read(0.0, &r));
  EXPECT_EQ(r.pedal, 0.7);
  pedal.close();
  ASSERT_TRUE(pen.read(0.001, &r));
  EXPECT_EQ(r.pedal, 0.0);
}

TEST(DevicePen, AnUnpluggedPenStaysFrozenAtRest) {
  test::FakePen fake;
  test::FakePedal pedal;
  ASSERT_TRUE(fake.open().ok());
  ASSERT_TRUE(pedal.open().ok());
  pedal.press(1.0);
  DevicePen pen(fake, quarterTurn(fake.spec()), &pedal);
  PenReading before, r;
  EXPECT_FALSE(DevicePen(fake, quarterTurn(fake.spec())).frozen());
  fake.setGrip({10, 0, 0}, {50, 0, 0});
  ASSERT_TRUE(pen.read(0.0, &before));
  fake.unplug();
  ASSERT_TRUE(pen.read(0.001, &r));
  EXPECT_TRUE(pen.frozen());
  EXPECT_EQ(r.grip, before.grip);
  EXPECT_EQ(r.velocity, Vec3{});
  EXPECT_EQ(r.pedal, 0.0);  // the drill is gone: the turbine stops
  EXPECT_EQ(pen.frozenReads(), 1u);
}

TEST(DevicePen, APenNeverSeenGivesNoReading) {
  test::FakePen fake;  // not opened: Disconnected
  DevicePen pen(fake, quarterTurn(fake.spec()));
  PenReading r;
  EXPECT_FALSE(pen.read(0.0, &r));
  EXPECT_FALSE(pen.frozen());
}

// The whole path under the real loop and recorder: a drill pen on a device and a pedal; the device
// is unplugged at step 150 and plugged back at step 220. The loop never stops, its force to the
// motors is zero while the device is away, the pen is recorded frozen, every step is in the file
// with the pedal as it was pressed, and after the replug the pen tracks and forces flow again.
TEST(DevicePen, UnplugMidSessionFaultsToZeroFreezesThePenAndKeepsTheRecording) {
  dentsim::test::Block block = dentsim::test::flatBlock(Material::Enamel);
  const SimParams params = defaultSimParams();
  const ToolModel bur = dentsim::test::sphereBur(0.2, 0.05);
  // The test plays the output side on the steady clock right after each step; a loaded machine can
  // preempt it for more than the 3 ms watchdog between the two, which would latch a Fault this test
  // is not about. The watchdog is timed exactly in safety_layer_test; here it is out of the way.
  SafetyParams safety;
  safety.watchdog_ms = 10'000;
  test::FakePen fake(safety);
  test::FakePedal pedal;
  ASSERT_TRUE(fake.open().ok());
  ASSERT_TRUE(pedal.open().ok());
  // Device mm onto the block 1:1, its origin 0.05 mm above the middle of the surface.
  DeviceMapping m;
  m.device_in_world.position = {0.8, 0.8, block.surface_mm + 0.05};
  DevicePen pen(fake, m, &pedal);
  dentsim::test::TempDir dir;
  const std::string file = dir.file("unplug.dses");
  constexpr uint64_t kSteps = 300, kUnplug = 150, kReplug = 220;
  std::vector<SafetyLayer::Output> motors;
  {
    HapticLoop loop(block.volume, block.frame, params, bur, nullptr, nullptr);
    loop.attach(PenRole::Drill, &pen);
    PenReading first;
    ASSERT_TRUE(pen.read(0.0, &first));
    loop.placeTool(PenRole::Drill, first.grip);
    SessionRecorder recorder;
    SessionInfo info = dentsim::test::sessionInfo("2026-11-22T10:00:00Z");
    info.rate_hz = params.device.rate_hz;
    info.drill_tool = "test_sphere";
    info.tooth_level = dentsim::test::Block::kLevel;
    info.voxel_mm = dentsim::test::Block::kVoxel;
    info.params_json = simParamsJson(params);
    info.tooth_hash = volumeHashHex(block.volume, block.frame);
    ASSERT_TRUE(recorder.start(loop, file, info).ok());
    ASSERT_TRUE(fake.enable().ok());
    for (uint64_t k = 0; k < kSteps; ++k) {
      // Down 1 um a step (into the enamel from step 50) until the replug, then lifted clear.
      const double z = k < kReplug ? -0.001 * double(k) : 0.5;
      fake.setGrip({0, 0, z}, {0, 0, k < kReplug ? -1.0 : 0.0});
      pedal.press(double(k % 10) / 10.0);
      if (k == kUnplug) fake.unplug();
      if (k == kReplug) {
        fake.replug();
        fake.home();
        ASSERT_TRUE(fake.enable().ok());
      }
      loop.step();
      motors.push_back(fake.sendToMotors(steadyNowNs()));
    }
    ASSERT_TRUE(recorder.finish(SessionEnd{kSteps, volumeHashHex(block.volume, block.frame), "completed"}).ok());
  }
  EXPECT_EQ(pen.frozenReads(), kReplug - kUnplug);
  // The motors: forces while plugged and in contact; exactly zero from the unplug to the replug.
  bool pushed_before = false;
  for (uint64_t k = 0; k < kUnplug; ++k) pushed_before |= norm(motors[k].wrench.force) > 0.05;
  EXPECT_TRUE(pushed_before) << "the pen never touched the enamel: the test proves nothing";
  for (uint64_t k = kUnplug; k < kReplug; ++k) {
    EXPECT_EQ(motors[k].wrench.force, Vec3{}) << k;
    EXPECT_EQ(motors[k].gate, SafetyGate::NotEnabled) << k;
  }
  EXPECT_EQ(motors.back().gate, SafetyGate::Pass);  // back, enabled, armed by the small force out of contact
  // The recording holds every step.
  auto rec = readSessionFile(file);
  ASSERT_TRUE(rec.ok()) << rec.message();
  ASSERT_EQ(rec->steps.size(), kSteps);
  const Pose frozen_at = rec->steps[kUnplug - 1].reading[0].grip;
  for (uint64_t k = 0; k < kSteps; ++k) {
    const SessionStep& s = rec->steps[k];
    ASSERT_TRUE(s.hasReading(0)) << k;
    const bool away = k >= kUnplug && k < kReplug;
    // The pedal as pressed (zero while the drill is away: the turbine stops with it).
    EXPECT_EQ(s.reading[0].pedal, away ? 0.0 : double(k % 10) / 10.0) << k;
    if (away) {
      EXPECT_EQ(s.reading[0].grip, frozen_at) << k;
      EXPECT_EQ(s.reading[0].velocity, Vec3{}) << k;
    } else {
      const double z = k < kReplug ? -0.001 * double(k) : 0.5;
      EXPECT_NEAR(s.reading[0].grip.position.z, block.surface_mm + 0.05 + z, 1e-12) << k;
    }
  }
}

}  // namespace
}  // namespace dentsim::devices
