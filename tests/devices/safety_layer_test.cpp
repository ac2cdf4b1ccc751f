// The safety layer: clamping keeps direction, the ramp-up after a small first command, the 3 ms watchdog, zero on disable and on a signal.
#include "devices/safety_layer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <thread>

#include "core/steady_clock.h"
#include "devices/fake_devices.h"

namespace dentsim::devices {
namespace {

constexpr int64_t kMs = 1'000'000;

// Limits 10 N and 200 N mm, enabled, armed at t = 0 and past its ramp by t = 1 s.
void arm(SafetyLayer& s, int64_t* now) {
  s.setLimits(10.0, 200.0);
  s.enable();
  s.command(Wrench{{0, 0, 0.1}, {}}, 0);
  EXPECT_EQ(s.output(0).gate, SafetyGate::Pass);
  *now = 1000 * kMs;
}

TEST(SafetyLayer, ClampKeepsTheDirection) {
  int64_t t = 0;
  SafetyLayer s;
  arm(s, &t);
  s.command(Wrench{{30, 40, 0}, {0, 0, -500}}, t);
  const SafetyLayer::Output o = s.output(t);
  EXPECT_EQ(o.gate, SafetyGate::Pass);
  EXPECT_TRUE(o.clamped);
  // 50 N along (0.6, 0.8, 0) becomes 10 N the same way: (6, 8, 0); the moment 200 along -z.
  EXPECT_NEAR(o.wrench.force.x, 6.0, 1e-12);
  EXPECT_NEAR(o.wrench.force.y, 8.0, 1e-12);
  EXPECT_EQ(o.wrench.force.z, 0.0);
  EXPECT_NEAR(o.wrench.moment.z, -200.0, 1e-9);
  // Within the limits, the command passes untouched.
  s.command(Wrench{{1, -2, 3}, {4, 5, 6}}, t + kMs);
  const SafetyLayer::Output p = s.output(t + kMs);
  EXPECT_FALSE(p.clamped);
  EXPECT_EQ(p.wrench.force, (Vec3{1, -2, 3}));
  EXPECT_EQ(p.wrench.moment, (Vec3{4, 5, 6}));
}

TEST(SafetyLayer, NonFiniteCommandsGiveZero) {
  int64_t t = 0;
  SafetyLayer s;
  arm(s, &t);
  s.command(Wrench{{NAN, 1, 1}, {}}, t);
  EXPECT_EQ(s.output(t).wrench.force, Vec3{});
  s.command(Wrench{{INFINITY, 0, 0}, {}}, t + 1);
  EXPECT_EQ(s.output(t + 1).wrench.force, Vec3{});
}

TEST(SafetyLayer, NoTorqueLimitMeansNoTorque) {
  SafetyLayer s;
  s.setLimits(10.0, 0.0);  // a 3-DOF pen
  s.enable();
  s.command(Wrench{{0, 0, 0.2}, {1, 2, 3}}, 0);
  const SafetyLayer::Output o = s.output(0);
  EXPECT_EQ(o.gate, SafetyGate::Pass);
  EXPECT_EQ(o.wrench.moment, Vec3{});
  EXPECT_EQ(o.wrench.force, (Vec3{0, 0, 0.2}));
}

TEST(SafetyLayer, NothingGoesOutUntilASmallFirstCommandThenTheCeilingRamps) {
  SafetyParams p;  // arm at 0.5 N, ramp over 0.5 s
  SafetyLayer s(p);
  s.setLimits(10.0, 0.0);
  s.enable();
  // Enabled with the tool deep in the tooth: 6 N asked, nothing sent.
  for (int64_t t = 0; t < 5 * kMs; t += kMs) {
    s.command(Wrench{{0, 0, 6}, {}}, t);
    const SafetyLayer::Output o = s.output(t);
    EXPECT_EQ(o.gate, SafetyGate::Disarmed) << t;
    EXPECT_EQ(o.wrench.force, Vec3{});
  }
  // The first small command arms it at t = 5 ms and passes.
  const int64_t armed = 5 * kMs;
  s.command(Wrench{{0, 0, 0.3}, {}}, armed);
  EXPECT_EQ(s.output(armed).wrench.force, (Vec3{0, 0, 0.3}));
  // Then the ceiling grows linearly: 0.5 + (10 - 0.5) * f after a fraction f of the ramp.
  for (double f : {0.1, 0.25, 0.5, 0.75}) {
    const int64_t t = armed + int64_t(f * 500 * kMs);
    s.command(Wrench{{0, -100, 0}, {}}, t);
    const SafetyLayer::Output o = s.output(t);
    EXPECT_TRUE(o.clamped);
    EXPECT_NEAR(-o.wrench.force.y, 0.5 + 9.5 * f, 1e-9) << f;
    EXPECT_EQ(o.wrench.force.x, 0.0);
  }
  const int64_t done = armed + 600 * kMs;
  s.command(Wrench{{0, -100, 0}, {}}, done);
  EXPECT_NEAR(-s.output(done).wrench.force.y, 10.0, 1e-9);
}

TEST(SafetyLayer, WatchdogZeroesWithin3msAndLatches) {
  int64_t t = 0;
  SafetyLayer s;
  arm(s, &t);
  s.command(Wrench{{0, 0, 2}, {}}, t);
  // 3.0 ms after the command it still passes; a microsecond later it is zero and latched.
  EXPECT_EQ(s.output(t + 3 * kMs).gate, SafetyGate::Pass);
  const SafetyLayer::Output late = s.output(t + 3 * kMs + 1000);
  EXPECT_EQ(late.gate, SafetyGate::Watchdog);
  EXPECT_EQ(late.wrench.force, Vec3{});
  EXPECT_TRUE(s.faulted());
  // Fresh commands do not clear it: a loop that stalled once is not trusted until re-enabled.
  s.command(Wrench{{0, 0, 0.1}, {}}, t + 5 * kMs);
  EXPECT_EQ(s.output(t + 5 * kMs).gate, SafetyGate::Watchdog);
  // disable + enable clears it, and the ramp starts again from a small command.
  s.disable();
  s.enable();
  EXPECT_FALSE(s.faulted());
  s.command(Wrench{{0, 0, 5}, {}}, t + 6 * kMs);
  EXPECT_EQ(s.output(t + 6 * kMs).gate, SafetyGate::Disarmed);
  s.command(Wrench{{0, 0, 0.1}, {}}, t + 7 * kMs);
  EXPECT_EQ(s.output(t + 7 * kMs).gate, SafetyGate::Pass);
}

// The haptic thread preempted inside command() (its sequence lock left odd: what a loaded machine
// did to DeviceSafety.WatchdogOnAnOutputThread) must not look like "nothing commanded since
// enabling": the command read before stands, and the watchdog counts from its stamp.
TEST(SafetyLayer, ACommandCaughtMidPublishKeepsThePreviousOneAndItsStamp) {
  SafetyLayer s;
  s.setLimits(10.0, 0.0);
  s.enable();
  ASSERT_EQ(s.output(0).gate, SafetyGate::Disarmed);  // the watchdog's clock starts here
  s.command(Wrench{{0, 0, 0.2}, {}}, 10 * kMs);
  ASSERT_EQ(s.output(10 * kMs).gate, SafetyGate::Pass);
  s.holdCommandForTest(true);
  const SafetyLayer::Output held = s.output(11 * kMs);
  EXPECT_EQ(held.gate, SafetyGate::Pass) << gateName(held.gate);
  EXPECT_EQ(held.wrench.force, (Vec3{0, 0, 0.2}));
  EXPECT_EQ(s.output(13 * kMs).gate, SafetyGate::Pass);
  // Still unreadable 3 ms after the last command read: that one is stale, so zero and latched.
  EXPECT_EQ(s.output(13 * kMs + 1).gate, SafetyGate::Watchdog);
  s.holdCommandForTest(false);
  s.command(Wrench{{0, 0, 0.2}, {}}, 14 * kMs);
  EXPECT_EQ(s.output(14 * kMs).gate, SafetyGate::Watchdog);
  EXPECT_TRUE(s.faulted());
}

// The watchdog counts from enabling (the first output after enable()) when the newest command is
// older than that; even then a command older than the watchdog never goes out, it gives zero.
TEST(SafetyLayer, ACommandFromBeforeEnablingNeverGoesOutOlderThanTheWatchdog) {
  SafetyLayer s;
  s.setLimits(10.0, 0.0);
  s.enable();
  s.command(Wrench{{0, 0, 0.2}, {}}, 0);
  // The output side runs first 2 ms later: the command is 2 ms old and passes (and arms).
  ASSERT_EQ(s.output(2 * kMs).gate, SafetyGate::Pass);
  EXPECT_EQ(s.output(3 * kMs).gate, SafetyGate::Pass);
  // 3 ms and a nanosecond old: zero, though the watchdog has counted only 1 ms since enabling.
  const SafetyLayer::Output old_command = s.output(3 * kMs + 1);
  EXPECT_EQ(old_command.gate, SafetyGate::Disarmed) << gateName(old_command.gate);
  EXPECT_EQ(old_command.wrench.force, Vec3{});
  EXPECT_FALSE(s.faulted());
  // 3 ms after enabling with nothing newer: the watchdog fires and latches.
  EXPECT_EQ(s.output(5 * kMs + 1).gate, SafetyGate::Watchdog);
  EXPECT_TRUE(s.faulted());
}

// The same, when the loop published a newer command that this side never read before the next
// publish was caught halfway: the newest complete stamp keeps the watchdog from firing early, and
// that one output is zero (the unread command's force is not at hand); the watchdog still fires
// once the loop really has published nothing complete for 3 ms.
TEST(SafetyLayer, AnUnreadNewerCommandKeepsTheWatchdogQuietWithZeroForce) {
  SafetyLayer s;
  s.setLimits(10.0, 0.0);
  s.enable();
  ASSERT_EQ(s.output(0).gate, SafetyGate::Disarmed);
  s.command(Wrench{{0, 0, 0.2}, {}}, 10 * kMs);
  ASSERT_EQ(s.output(10 * kMs).gate, SafetyGate::Pass);
  s.command(Wrench{{0, 0, 0.3}, {}}, 12 * kMs);  // published, never read by this side
  s.holdCommandForTest(true);                     // the next publish caught halfway
  const SafetyLayer::Output held = s.output(13 * kMs + 500'000);  // 3.5 ms after the last read
  EXPECT_EQ(held.gate, SafetyGate::Pass) << gateName(held.gate);
  EXPECT_EQ(held.wrench.force, Vec3{});
  EXPECT_FALSE(s.faulted());
  EXPECT_EQ(s.output(15 * kMs).gate, SafetyGate::Pass);
  EXPECT_EQ(s.output(15 * kMs + 1).gate, SafetyGate::Watchdog);
  s.holdCommandForTest(false);
}

TEST(SafetyLayer, EnabledButNeverCommandedFaultsAfterTheWatchdog) {
  SafetyLayer s;
  s.setLimits(10.0, 0.0);
  s.enable();
  EXPECT_EQ(s.output(100 * kMs).gate, SafetyGate::Disarmed);  // the clock starts at the first output
  EXPECT_EQ(s.output(103 * kMs).gate, SafetyGate::Disarmed);
  EXPECT_EQ(s.output(103 * kMs + 1).gate, SafetyGate::Watchdog);
}

// Two pens of one student: the drill's watchdog fires, and the mirror, still commanded and
// fresh, gives zero from its next output on; clearing the group (a new segment) lets it through.
TEST(SafetyLayer, AFaultOnOnePenOfAGroupZeroesTheOtherUntilTheGroupIsCleared) {
  SafetyGroup hands;
  SafetyLayer drill, mirror;
  drill.joinGroup(&hands, 0);
  mirror.joinGroup(&hands, 1);
  int64_t t = 0;
  arm(drill, &t);
  arm(mirror, &t);
  drill.command(Wrench{{0, 0, 0.2}, {}}, t);
  mirror.command(Wrench{{0.1, 0, 0}, {}}, t);
  EXPECT_EQ(drill.output(t).gate, SafetyGate::Pass);
  EXPECT_EQ(mirror.output(t).gate, SafetyGate::Pass);
  // The drill's loop stalls; the mirror's keeps commanding.
  mirror.command(Wrench{{0.1, 0, 0}, {}}, t + 4 * kMs);
  EXPECT_EQ(drill.output(t + 4 * kMs).gate, SafetyGate::Watchdog);
  const SafetyLayer::Output held = mirror.output(t + 4 * kMs);
  EXPECT_EQ(held.gate, SafetyGate::OtherPen);
  EXPECT_EQ(held.wrench.force, Vec3{});
  EXPECT_FALSE(mirror.faulted()) << "held, not faulted: it did nothing wrong";
  EXPECT_EQ(hands.firstFault(), 0);
  // A backend's own fault halts the group the same way (HapticDevice::setState(Fault)).
  hands.clear();
  EXPECT_EQ(mirror.output(t + 4 * kMs).gate, SafetyGate::Pass);
  mirror.haltGroup();
  EXPECT_EQ(hands.firstFault(), 1);
  EXPECT_EQ(mirror.output(t + 4 * kMs).gate, SafetyGate::OtherPen);
}

TEST(DeviceSafety, ADeviceGoingToFaultHaltsItsGroup) {
  SafetyGroup hands;
  test::FakePen drill, mirror;
  drill.joinSafetyGroup(&hands, 0);
  mirror.joinSafetyGroup(&hands, 1);
  ASSERT_TRUE(drill.open().ok() && mirror.open().ok());
  ASSERT_TRUE(drill.enable().ok() && mirror.enable().ok());
  drill.command(Wrench{{0, 0, 0.2}, {}}, 0);
  mirror.command(Wrench{{0, 0, 0.2}, {}}, 0);
  EXPECT_EQ(drill.sendToMotors(0).gate, SafetyGate::Pass);
  EXPECT_EQ(mirror.sendToMotors(0).gate, SafetyGate::Pass);
  // The drill's watchdog: the device goes to Fault, and the mirror's next packet is zero.
  mirror.command(Wrench{{0, 0, 0.2}, {}}, 4 * kMs);
  EXPECT_EQ(drill.sendToMotors(4 * kMs).gate, SafetyGate::Watchdog);
  EXPECT_EQ(drill.state(), DeviceState::Fault);
  EXPECT_EQ(mirror.sendToMotors(4 * kMs).wrench.force, Vec3{});
  EXPECT_EQ(mirror.state(), DeviceState::Enabled);
}

TEST(SafetyLayer, DisableGivesZeroAtOnce) {
  int64_t t = 0;
  SafetyLayer s;
  arm(s, &t);
  s.command(Wrench{{0, 3, 0}, {}}, t);
  EXPECT_EQ(s.output(t).wrench.force, (Vec3{0, 3, 0}));
  s.disable();
  const SafetyLayer::Output o = s.output(t);
  EXPECT_EQ(o.gate, SafetyGate::NotEnabled);
  EXPECT_EQ(o.wrench.force, Vec3{});
}

TEST(SafetyLayer, ASignalZeroesEveryLayer) {
  int64_t t = 0;
  SafetyLayer a, b;
  arm(a, &t);
  arm(b, &t);
  installDeviceSignalHandlers();
  a.command(Wrench{{1, 0, 0}, {}}, t);
  b.command(Wrench{{0, 1, 0}, {}}, t);
  ASSERT_EQ(a.output(t).gate, SafetyGate::Pass);
  ASSERT_EQ(std::raise(SIGTERM), 0);  // the first signal only sets the flag
  EXPECT_TRUE(allDevicesZeroRequested());
  for (SafetyLayer* s : {&a, &b}) {
    const SafetyLayer::Output o = s->output(t);
    EXPECT_EQ(o.gate, SafetyGate::Stopping);
    EXPECT_EQ(o.wrench.force, Vec3{});
  }
  clearAllDevicesZeroForTest();
  std::signal(SIGTERM, SIG_DFL);
  EXPECT_EQ(a.output(t).gate, SafetyGate::Pass);
}

// A loop thread commands with rising demands while an output thread samples: no output ever
// exceeds the limit, and every direction is kept. The loop holds its demand small until the output
// side has armed. The watchdog is out of the way here (a loaded machine may stall either thread
// for milliseconds); the tests above time it exactly. The output side samples for at least 60 ms
// and until it has seen a force above the first demand: a loaded machine may starve it for all of
// a fixed window, so the window ends on what was seen, and 10 s only bounds a failure.
TEST(SafetyLayer, ConcurrentCommandAndOutputNeverExceedTheCeiling) {
  SafetyParams params;
  params.watchdog_ms = 10'000;
  SafetyLayer s(params);
  s.setLimits(4.0, 0.0);
  s.enable();
  std::atomic<bool> done{false}, armed{false}, started{false};
  std::thread loop([&] {
    double demand = 0.1;
    while (!done) {
      if (armed) demand += 0.01;
      s.command(Wrench{{demand * 0.6, 0, -demand * 0.8}, {}}, steadyNowNs());
      started = true;
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  });
  while (!started) std::this_thread::yield();
  uint64_t passed = 0;
  double largest = 0.0;
  const int64_t t0 = steadyNowNs();
  for (int64_t t = t0; t - t0 < 10'000 * kMs && (t - t0 < 60 * kMs || !(largest > 0.1)); t = steadyNowNs()) {
    const SafetyLayer::Output o = s.output(steadyNowNs());
    const double n = norm(o.wrench.force);
    EXPECT_LE(n, 4.0 + 1e-12);
    largest = std::max(largest, n);
    if (o.gate == SafetyGate::Pass) armed = true;
    if (n > 0) {
      ++passed;
      EXPECT_NEAR(o.wrench.force.x / n, 0.6, 1e-9);
      EXPECT_NEAR(o.wrench.force.z / n, -0.8, 1e-9);
    }
  }
  done = true;
  loop.join();
  EXPECT_GT(passed, 0u);
  EXPECT_GT(largest, 0.1);
}

// ---- through a device ----

TEST(DeviceSafety, EnableNeedsReadyAndAWatchdogFaultMovesTheDeviceToFault) {
  test::FakePen pen;
  ASSERT_TRUE(pen.open().ok());
  ASSERT_EQ(pen.state(), DeviceState::Ready);
  ASSERT_TRUE(pen.enable().ok());
  EXPECT_EQ(pen.state(), DeviceState::Enabled);
  pen.command(Wrench{{0, 0, 0.2}, {}}, 0);
  EXPECT_EQ(pen.sendToMotors(1 * kMs).wrench.force, (Vec3{0, 0, 0.2}));
  // Forces go to the motors clamped to the spec: 10 N.
  pen.command(Wrench{{0, 0, 50}, {}}, 900 * kMs);
  EXPECT_NEAR(pen.sendToMotors(900 * kMs).wrench.force.z, 10.0, 1e-12);
  // No command for more than 3 ms: zero, and the device is in Fault with the reason.
  EXPECT_EQ(pen.sendToMotors(903 * kMs + 1).wrench.force, Vec3{});
  EXPECT_EQ(pen.state(), DeviceState::Fault);
  EXPECT_NE(pen.reason().find("watchdog"), std::string::npos) << pen.reason();
  EXPECT_FALSE(pen.enable().ok());  // not from Fault: disable first
  pen.disable();
  EXPECT_EQ(pen.state(), DeviceState::Ready);
  EXPECT_TRUE(pen.enable().ok());
}

TEST(DeviceSafety, ZeroWhileNotHomedAndOnDisableAndClose) {
  test::FakePen pen;
  pen.unplug();
  pen.replug();  // back, but not homed
  ASSERT_EQ(pen.state(), DeviceState::NeedsHoming);
  EXPECT_FALSE(pen.enable().ok());
  pen.command(Wrench{{0, 0, 0.2}, {}}, 0);
  EXPECT_EQ(pen.sendToMotors(0).gate, SafetyGate::NotEnabled);
  pen.home();
  ASSERT_TRUE(pen.enable().ok());
  pen.command(Wrench{{0, 0, 0.2}, {}}, kMs);
  EXPECT_EQ(pen.sendToMotors(kMs).wrench.force, (Vec3{0, 0, 0.2}));
  pen.disable();
  EXPECT_EQ(pen.sendToMotors(kMs).wrench.force, Vec3{});
  ASSERT_TRUE(pen.enable().ok());
  pen.command(Wrench{{0, 0, 0.2}, {}}, 2 * kMs);
  EXPECT_EQ(pen.sendToMotors(2 * kMs).gate, SafetyGate::Pass);
  pen.close();
  EXPECT_EQ(pen.sent().back().wrench.force, Vec3{});
  EXPECT_EQ(pen.state(), DeviceState::Disconnected);
}

// A real output thread at about 2 kHz beside a commanding thread that then stops. Judged by the
// command stamps (a loaded machine may stall either thread): every force sent had a command at most
// 3 ms old, the zero came only once the newest command was older than that, and it latched a Fault.
// Both threads run at once on two cores, so each side also notes when its call returned: a command
// counts as seen by an output only if command() had returned before the output began, and as able
// to have passed one only if it was stamped before the output returned. No slack is guessed.
TEST(DeviceSafety, WatchdogOnAnOutputThread) {
  test::FakePen pen;
  ASSERT_TRUE(pen.open().ok());
  ASSERT_TRUE(pen.enable().ok());
  std::atomic<bool> stop{false};
  struct Sent {
    int64_t begun, returned;  // steady clock around sendToMotors() [ns]
    SafetyLayer::Output output;
  };
  std::vector<Sent> log;
  std::thread io([&] {
    while (!stop) {
      const int64_t now = steadyNowNs();
      const SafetyLayer::Output o = pen.sendToMotors(now);
      log.push_back({now, steadyNowNs(), o});
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  });
  struct Commanded {
    int64_t stamp, returned;  // the command's stamp and when command() returned [ns]
  };
  std::vector<Commanded> commands;
  for (int k = 0; k < 50; ++k) {
    const int64_t now = steadyNowNs();
    pen.command(Wrench{{0, 0, 0.2}, {}}, now);
    commands.push_back({now, steadyNowNs()});
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  // Only bounds how long a watchdog that never fires takes to fail the test.
  const int64_t give_up = steadyNowNs() + 10'000 * kMs;
  while (pen.state() != DeviceState::Fault && steadyNowNs() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  stop = true;
  io.join();
  ASSERT_EQ(pen.state(), DeviceState::Fault);
  // The newest stamp among the commands that pass `counts`, or INT64_MIN when none does.
  const auto newest = [&](auto counts) {
    int64_t s = INT64_MIN;
    for (const Commanded& c : commands) {
      if (counts(c)) s = std::max(s, c.stamp);
    }
    return s;
  };
  bool seen_zero = false;
  for (const Sent& e : log) {
    if (e.output.gate == SafetyGate::Pass) {
      ASSERT_FALSE(seen_zero) << "force out again after the watchdog";
      EXPECT_LE(e.begun - newest([&](const Commanded& c) { return c.stamp <= e.returned; }), 3 * kMs);
    } else if (e.output.gate == SafetyGate::Watchdog) {
      if (!seen_zero) {
        EXPECT_GT(e.begun - newest([&](const Commanded& c) { return c.returned <= e.begun; }), 3 * kMs);
      }
      seen_zero = true;
      EXPECT_EQ(e.output.wrench.force, Vec3{});
    }
  }
  EXPECT_TRUE(seen_zero);
}

}  // namespace
}  // namespace dentsim::devices
