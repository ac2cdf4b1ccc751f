// Tests for devices/openhaptics_pen.cpp: a missing or wrong HDAPI library, and the pen driven against the fake HDAPI in tests/devices/fake_hd.
#include "devices/openhaptics_pen.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <thread>

#include "devices/fake_hd/fake_hd_controls.h"
#include "devices/fake_sysfs.h"
#include "unprivileged.h"

namespace dentsim::devices {
namespace {

using Clock = std::chrono::steady_clock;

int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// ---- without the library ----

TEST(OpenHapticsPen, AbsentLibraryIsDisconnectedWithAReason) {
  OpenHapticsOptions options;
  options.library = "/nonexistent/dentsim-test/libHD.so";
  const auto entries = enumerateOpenHaptics(options);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].name, "openhaptics:Default");
  EXPECT_EQ(entries[0].state, DeviceState::Disconnected);
  EXPECT_EQ(entries[0].reason,
            "OpenHaptics not installed (/nonexistent/dentsim-test/libHD.so not found; set DENTSIM_OPENHAPTICS_LIB)");

  auto pen = makeOpenHapticsPen("Default", options);
  const Status s = pen->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), "openhaptics:Default: OpenHaptics not installed (/nonexistent/dentsim-test/libHD.so not "
                         "found; set DENTSIM_OPENHAPTICS_LIB)");
  EXPECT_EQ(s.message().find('\n'), std::string::npos);
  EXPECT_EQ(pen->state(), DeviceState::Disconnected);
  EXPECT_FALSE(pen->enable().ok());
  DeviceReading r;
  EXPECT_FALSE(pen->read(0.0, &r));
  pen->close();
  EXPECT_EQ(pen->state(), DeviceState::Disconnected);
}

TEST(OpenHapticsPen, LibraryWithoutHdapiNamesTheMissingSymbol) {
  OpenHapticsOptions options;
  options.library = "libm.so.6";  // loads fine, exports no hd* function
  auto pen = makeOpenHapticsPen("Default", options);
  const Status s = pen->open();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("libm.so.6"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("missing symbol hdInitDevice"), std::string::npos) << s.message();
  EXPECT_EQ(pen->state(), DeviceState::Disconnected);
  EXPECT_EQ(pen->reason(), s.message().substr(std::string("openhaptics:Default: ").size()));
}

// ---- against the fake HDAPI ----

using test::FakeHd;
using test::waitFor;
constexpr unsigned kCalibrationNeedsUpdate = test::kHdCalibrationNeedsUpdate;
constexpr unsigned kCalibrationNeedsManualInput = test::kHdCalibrationNeedsManualInput;
constexpr int kCalibrationAuto = test::kHdCalibrationAuto;
constexpr int kCalibrationInkwell = test::kHdCalibrationInkwell;
constexpr unsigned kCommError = test::kHdCommError;
constexpr double kTouchMaxForceN = test::kFakeTouchMaxForceN;

class OpenHapticsFake : public ::testing::Test {
 protected:
  void SetUp() override {
    if (test::kFakeHdLibrary == nullptr) GTEST_SKIP() << "the fake HDAPI library was not built (DENTSIM_FAKE_HD_LIB unset)";
    fake_.load();
    if (HasFatalFailure()) return;
    fake_.reset();
    options_.library = test::kFakeHdLibrary;
    // A watchdog the test's command thread cannot trip when starved on a loaded machine (the one
    // test about the watchdog sets its own), and a short ramp.
    options_.safety.watchdog_ms = 1000;
    options_.safety.ramp_s = 0.05;
  }
  void TearDown() override {
    stopCommanding();
    pen_.reset();
    fake_.unload();
  }

  void openPen(const std::string& device = "Default") {
    pen_ = makeOpenHapticsPen(device, options_);
    const Status s = pen_->open();
    ASSERT_TRUE(s.ok()) << s.message();
  }

  // A stand-in haptic loop: commands `force` every 0.5 ms until stopped.
  void startCommanding() {
    commanding_.store(true);
    commander_ = std::thread([this] {
      while (commanding_.load()) {
        pen_->command(Wrench{{commanded_[0].load(), commanded_[1].load(), commanded_[2].load()}, {}}, nowNs());
        std::this_thread::sleep_for(std::chrono::microseconds(500));
      }
    });
  }
  void stopCommanding() {
    commanding_.store(false);
    if (commander_.joinable()) commander_.join();
  }
  // Component by component: a tear between them lasts one command, 0.5 ms, and no test looks that close.
  void commandForce(const Vec3& f) {
    for (int a = 0; a < 3; ++a) commanded_[a].store(f[a]);
  }

  // Waits for two full frames, so the fake's latest numbers went through the servo loop.
  void waitFrames(long n = 2) {
    const long start = fake_.frames();
    ASSERT_TRUE(waitFor([&] { return fake_.frames() >= start + n; }));
  }

  FakeHd fake_;
  OpenHapticsOptions options_;
  std::unique_ptr<HapticDevice> pen_;
  std::atomic<double> commanded_[3]{};
  std::atomic<bool> commanding_{false};
  std::thread commander_;
};

TEST_F(OpenHapticsFake, OpenReadsSpecAndPose) {
  // A 90 degree turn about z, column-major: the first column is the image of x, (0, 1, 0).
  const double transform[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 12.5, -3.25, 40, 1};
  const double position[3] = {12.5, -3.25, 40};
  const double velocity[3] = {1.5, -2, 30};
  const double angular[3] = {0.1, 0.2, -0.3};
  fake_.setPose(position, velocity, angular, transform);
  fake_.setButtons(0b10);
  openPen();
  EXPECT_EQ(pen_->state(), DeviceState::Ready);
  EXPECT_EQ(pen_->name(), "openhaptics:Default");
  EXPECT_EQ(pen_->spec().model, "Touch");
  EXPECT_DOUBLE_EQ(pen_->spec().max_force_n, kTouchMaxForceN);
  EXPECT_DOUBLE_EQ(pen_->spec().max_torque_n_mm, 0.0);  // 3 output DOF: force only
  EXPECT_DOUBLE_EQ(pen_->spec().workspace_min_mm.x, -80);
  EXPECT_DOUBLE_EQ(pen_->spec().workspace_max_mm.z, 35);
  EXPECT_TRUE(pen_->spec().senses_rotation);
  waitFrames();

  DeviceReading r;
  // read() never waits: a read that meets the servo thread mid-store gives the previous sample.
  ASSERT_TRUE(waitFor([&] { return pen_->read(0.0, &r) && r.pose.position.x == 12.5; }));
  EXPECT_NEAR(r.pose.position.x, 12.5, 1e-9);
  EXPECT_NEAR(r.pose.position.y, -3.25, 1e-9);
  EXPECT_NEAR(r.pose.position.z, 40, 1e-9);
  EXPECT_NEAR(r.velocity.x, 1.5, 1e-9);
  EXPECT_NEAR(r.velocity.y, -2, 1e-9);
  EXPECT_NEAR(r.velocity.z, 30, 1e-9);
  EXPECT_NEAR(r.angular_velocity.z, -0.3, 1e-9);
  EXPECT_EQ(r.buttons, 0b10u);
  // 90 degrees about z: (cos 45, 0, 0, sin 45).
  EXPECT_NEAR(std::abs(r.pose.rotation.w), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(r.pose.rotation.z * (r.pose.rotation.w < 0 ? -1 : 1), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(r.pose.rotation.x, 0, 1e-9);
  EXPECT_NEAR(r.pose.rotation.y, 0, 1e-9);
  const Vec3 x_axis = r.pose.rotation.rotate({1, 0, 0});
  EXPECT_NEAR(x_axis.y, 1, 1e-9);
  EXPECT_GT(r.stamp_ns, 0);

  // A later pose reaches read() too.
  const double moved[3] = {-7, 8, 9};
  fake_.setPose(moved, velocity, angular, nullptr);
  fake_.setButtons(0b01);
  waitFrames();
  ASSERT_TRUE(waitFor([&] { return pen_->read(0.0, &r) && r.pose.position.x == -7; }));
  EXPECT_NEAR(r.pose.position.x, -7, 1e-9);
  EXPECT_EQ(r.buttons, 0b01u);
  EXPECT_EQ(fake_.force(), Vec3{});  // Ready: nothing goes out
}

TEST_F(OpenHapticsFake, UnknownDeviceIsDisconnectedNamingIt) {
  pen_ = makeOpenHapticsPen("Omni2", options_);
  const Status s = pen_->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(pen_->state(), DeviceState::Disconnected);
  EXPECT_NE(pen_->reason().find("hdInitDevice(\"Omni2\")"), std::string::npos) << pen_->reason();
  EXPECT_NE(pen_->reason().find("no such device configuration"), std::string::npos) << pen_->reason();
  EXPECT_NE(pen_->reason().find("0x0300"), std::string::npos) << pen_->reason();
  EXPECT_EQ(s.message(), "openhaptics:Omni2: " + pen_->reason());
  EXPECT_EQ(fake_.schedulerRunning(), 0);
}

TEST_F(OpenHapticsFake, ForceIsArmedRampedAndClampedKeepingDirection) {
  openPen();
  ASSERT_TRUE(pen_->enable().ok());
  EXPECT_EQ(pen_->state(), DeviceState::Enabled);

  // |F| = 10 N along (0.6, 0.8, 0): too large to arm the ramp, so nothing may pass.
  commandForce({6, 8, 0});
  startCommanding();
  waitFrames(30);
  EXPECT_EQ(fake_.force(), Vec3{});

  // A 0.1 N command (below arm_force_n = 0.5 N) arms it and passes as it is.
  commandForce({0.06, 0.08, 0});
  ASSERT_TRUE(waitFor([&] { return norm(fake_.force()) > 0; }));
  EXPECT_NEAR(fake_.force().x, 0.06, 1e-12);
  EXPECT_NEAR(fake_.force().y, 0.08, 1e-12);

  // After the 50 ms ramp the big command is cut to HD_NOMINAL_MAX_FORCE, same direction:
  // 3.3 N x (0.6, 0.8, 0) = (1.98, 2.64, 0).
  commandForce({6, 8, 0});
  ASSERT_TRUE(waitFor([&] { return norm(fake_.force()) > kTouchMaxForceN - 1e-9; }));
  const Vec3 f = fake_.force();
  EXPECT_NEAR(norm(f), kTouchMaxForceN, 1e-9);
  EXPECT_NEAR(f.x, 1.98, 1e-9);
  EXPECT_NEAR(f.y, 2.64, 1e-9);
  EXPECT_NEAR(f.z, 0.0, 1e-12);

  // disable(): zero from the next frame on, Ready again.
  pen_->disable();
  EXPECT_EQ(pen_->state(), DeviceState::Ready);
  ASSERT_TRUE(waitFor([&] { return fake_.force() == Vec3{}; }, 10000));
  waitFrames(5);
  EXPECT_EQ(fake_.force(), Vec3{});
}

TEST_F(OpenHapticsFake, StalledCommandsTripTheWatchdogToZeroAndFault) {
  // Long enough that the commanding thread, starved on a loaded machine, does not trip it before
  // the force is seen; what matters is that the stop trips it.
  options_.safety.watchdog_ms = 300;
  openPen();
  ASSERT_TRUE(pen_->enable().ok());
  commandForce({0.3, 0, 0});
  startCommanding();
  ASSERT_TRUE(waitFor([&] { return fake_.force().x > 0; }));
  stopCommanding();
  // How soon is the safety layer's to keep (its tests pass explicit stamps: zero 3.0 ms after the
  // last command, not 2.999); here the stalled commands must reach the motors as zero and a Fault,
  // through the servo loop. The bounds only decide how long a failure is waited for.
  ASSERT_TRUE(waitFor([&] { return fake_.force() == Vec3{}; }, 10000));
  ASSERT_TRUE(waitFor([&] { return pen_->state() == DeviceState::Fault; }, 10000));
  EXPECT_NE(pen_->reason().find("watchdog"), std::string::npos) << pen_->reason();
  // The servo loop keeps sampling (zero force) and stays at zero.
  waitFrames(5);
  EXPECT_EQ(fake_.force(), Vec3{});
  // disable + enable clears a watchdog fault.
  pen_->disable();
  EXPECT_EQ(pen_->state(), DeviceState::Ready);
}

TEST_F(OpenHapticsFake, InjectedHdErrorFaultsWithZeroForceAndStopsTheLoop) {
  openPen();
  ASSERT_TRUE(pen_->enable().ok());
  commandForce({0.2, 0.1, 0});
  startCommanding();
  ASSERT_TRUE(waitFor([&] { return norm(fake_.force()) > 0; }));
  fake_.injectError(kCommError, 7);
  ASSERT_TRUE(waitFor([&] { return pen_->state() == DeviceState::Fault; }));
  EXPECT_NE(pen_->reason().find("communication error (fake HDAPI)"), std::string::npos) << pen_->reason();
  EXPECT_NE(pen_->reason().find("0x0302"), std::string::npos) << pen_->reason();
  EXPECT_EQ(fake_.force(), Vec3{});
  EXPECT_EQ(fake_.forceOutputEnabled(), 0);
  // The pen is served no more: no more frames, the command thread notwithstanding. The shared
  // servo callback stays scheduled (it would serve another pen) until the pen is closed.
  const long frames = fake_.frames();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(fake_.frames(), frames);
  EXPECT_EQ(fake_.scheduledCallbacks(), 1);
  // An HD fault is not cleared by disable(); enable() refuses; read() has nothing.
  pen_->disable();
  EXPECT_EQ(pen_->state(), DeviceState::Fault);
  EXPECT_FALSE(pen_->enable().ok());
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));
  pen_->close();
  EXPECT_EQ(fake_.scheduledCallbacks(), 0);
  EXPECT_EQ(fake_.schedulerRunning(), 0);
}

// A pen HDAPI cannot open while a Touch's serial node is closed to the user: the one line names
// the node and the udev rule, and keeps HDAPI's own words. Checked as the user nobody in a forked
// child (the tests run as root, whom every mode lets in), against a fake sysfs tree.
TEST_F(OpenHapticsFake, AnOpenThatFailsOnAClosedTouchNodeNamesTheUdevRule) {
  if (const std::string why = dentsim::test::whyNotNobody(); !why.empty()) GTEST_SKIP() << why;
  dentsim::test::FakeSys sys;
  sys.addUsbTty("ttyACM0", "2988", 1);
  const auto node = sys.addNode("ttyACM0", std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  options_.sysfs_root = sys.sys().string();
  options_.dev_root = sys.dev().string();
  // "Missing" names no configured pen, so hdInitDevice fails as it does for a pen it cannot reach.
  const std::string line = dentsim::test::inChildAsNobody([&] {
    auto pen = makeOpenHapticsPen("Missing", options_);
    const Status s = pen->open();
    return s.ok() ? std::string("opened") : s.message();
  });
  EXPECT_EQ(line.rfind("openhaptics:Missing: permission denied on " + node.string() + ": install devices/70-dentsim.rules", 0),
            0u) << line;
  EXPECT_NE(line.find("hdInitDevice(\"Missing\")"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  // As root the node opens, so the line is HDAPI's alone.
  auto pen = makeOpenHapticsPen("Missing", options_);
  const Status s = pen->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message().find("permission denied"), std::string::npos) << s.message();
}

TEST_F(OpenHapticsFake, CalibrationNeedingTheUserIsNeedsHoming) {
  fake_.setCalibration(kCalibrationNeedsManualInput, kCalibrationInkwell);
  openPen();
  EXPECT_EQ(pen_->state(), DeviceState::NeedsHoming);
  EXPECT_NE(pen_->reason().find("inkwell"), std::string::npos) << pen_->reason();
  EXPECT_FALSE(pen_->enable().ok());
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));
  EXPECT_EQ(fake_.calibrationUpdates(nullptr), 0);  // nothing the library can do by itself

  // The user puts the stylus in the inkwell: the next service() finds it calibrated.
  fake_.setCalibration(0x5000, kCalibrationInkwell);
  ASSERT_TRUE(waitFor([&] {
    pen_->service();
    return pen_->state() == DeviceState::Ready;
  }));
  EXPECT_TRUE(waitFor([&] { return pen_->read(0.0, &r); }));
}

TEST_F(OpenHapticsFake, CalibrationNeedingAnUpdateIsUpdatedAutomatically) {
  fake_.setCalibration(kCalibrationNeedsUpdate, kCalibrationAuto);
  openPen();
  EXPECT_EQ(pen_->state(), DeviceState::Ready) << pen_->reason();
  unsigned style = 0;
  EXPECT_EQ(fake_.calibrationUpdates(&style), 1);
  EXPECT_EQ(style, static_cast<unsigned>(kCalibrationAuto));
}

TEST_F(OpenHapticsFake, TorquePensGetTheMomentInMilliNewtonMetres) {
  fake_.setTorqueOutput(200.0);  // [mN m] = 200 N mm
  openPen();
  EXPECT_DOUBLE_EQ(pen_->spec().max_torque_n_mm, 200.0);
  ASSERT_TRUE(pen_->enable().ok());
  commanding_.store(true);
  commander_ = std::thread([this] {
    while (commanding_.load()) {
      pen_->command(Wrench{{0.1, 0, 0}, {0, 0, 15}}, nowNs());  // 15 N mm = 15 mN m
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  });
  double torque[3] = {0, 0, 0};
  ASSERT_TRUE(waitFor([&] {
    fake_.sent(nullptr, torque);
    return torque[2] > 14.9;
  }));
  EXPECT_NEAR(torque[2], 15.0, 1e-9);
}

TEST_F(OpenHapticsFake, CloseIsIdempotentAndStopsEverything) {
  openPen();
  ASSERT_TRUE(pen_->enable().ok());
  EXPECT_EQ(fake_.schedulerRunning(), 1);
  EXPECT_EQ(fake_.scheduledCallbacks(), 1);
  EXPECT_EQ(fake_.deviceInitialized(), 1);
  pen_->close();
  EXPECT_EQ(pen_->state(), DeviceState::Disconnected);
  EXPECT_EQ(fake_.schedulerRunning(), 0);
  EXPECT_EQ(fake_.scheduledCallbacks(), 0);
  EXPECT_EQ(fake_.deviceInitialized(), 0);
  EXPECT_EQ(fake_.force(), Vec3{});
  const long frames = fake_.frames();
  pen_->close();
  EXPECT_EQ(pen_->state(), DeviceState::Disconnected);
  EXPECT_EQ(fake_.frames(), frames);
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));

  // It opens again after a close, and the destructor closes it.
  ASSERT_TRUE(pen_->open().ok());
  EXPECT_EQ(pen_->state(), DeviceState::Ready);
  pen_.reset();
  EXPECT_EQ(fake_.schedulerRunning(), 0);
  EXPECT_EQ(fake_.deviceInitialized(), 0);
}

TEST_F(OpenHapticsFake, EnumerateProbesTheDefaultPen) {
  auto entries = enumerateOpenHaptics(options_);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].name, "openhaptics:Default");
  EXPECT_EQ(entries[0].model, "Touch");
  EXPECT_EQ(entries[0].state, DeviceState::Ready);
  EXPECT_TRUE(entries[0].reason.empty());
  EXPECT_EQ(fake_.deviceInitialized(), 0);  // the probe let it go

  fake_.setCalibration(kCalibrationNeedsManualInput, kCalibrationInkwell);
  entries = enumerateOpenHaptics(options_);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].state, DeviceState::NeedsHoming);
  EXPECT_NE(entries[0].reason.find("inkwell"), std::string::npos);
}

}  // namespace
}  // namespace dentsim::devices
