// Tests for devices/falcon_device.cpp against a fake Falcon in a umockdev testbed: enumeration, firmware load, homing, the loop, faults.
#include <gtest/gtest.h>
#include <umockdev.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "devices/falcon_device.h"
#include "devices/falcon_kinematics.h"
#include "fake_falcon.h"

namespace dentsim::devices {
namespace {

using testing::ControlSetup;
using testing::FakeFalcon;

// The FTDI requests of the running firmware's mode, written out from the FTDI request set.
const std::vector<ControlSetup> kFirmwareMode = {
    {0x40, 0x09, 1, 0},       // latency timer 1 ms
    {0x40, 0x03, 0x0002, 0},  // baud divisor 2: 1.5 Mbaud
    {0x40, 0x00, 1, 0},       // purge RX
    {0x40, 0x00, 2, 0},       // purge TX
};
const std::vector<ControlSetup> kLoaderMode = {
    {0x40, 0x00, 1, 0},       {0x40, 0x00, 2, 0},       // purge RX, TX
    {0x40, 0x09, 16, 0},                                // latency 16 ms
    {0x40, 0x03, 0x4138, 0},                            // 9600 baud
    {0x40, 0x04, 0x0008, 0},                            // 8N1
    {0x40, 0x02, 0x0000, 0},                            // no flow control
    {0x40, 0x01, 0x0200, 0},                            // RTS low
    {0x40, 0x01, 0x0100, 0},  {0x40, 0x01, 0x0101, 0},  // DTR low, high: reset into the loader
    {0x40, 0x01, 0x0100, 0},                            // DTR low
    {0x40, 0x03, 0x0015, 0},                            // ~140 kbaud for the upload
};

// Commands as bytes: every nibble 'A' + value; the status byte 'A' + (LED bits | homing bit).
const std::string kHomingCommand = "<AAAAAAAAAAAAJA>";  // red (8) | homing (1) = 9 -> 'J'
const std::string kHomedCommand = "<AAAAAAAAAAAACA>";   // green (2) -> 'C'
const std::string kZeroCommand = "<AAAAAAAAAAAAAA>";

// Polls done() until it holds or `seconds` pass. The limit only bounds how long a failure takes to
// show, so it is far longer than the I/O thread needs even when a loaded machine starves it.
template <class F>
bool waitFor(F done, double seconds = 20.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return done();
}

std::vector<ControlSetup> concat(std::initializer_list<std::vector<ControlSetup>> parts) {
  std::vector<ControlSetup> all;
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

class FalconUsb : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    if (!preload || !std::strstr(preload, "libumockdev-preload"))
      GTEST_SKIP() << "umockdev is missing: these tests run under umockdev-wrapper (Debian package umockdev)";
    testbed_ = umockdev_testbed_new();
    gchar* root = umockdev_testbed_get_root_dir(testbed_);  // ours to free
    dir_ = root;
    g_free(root);
    options_.firmware_path = dir_ + "/no_such_firmware.bin";
    options_.safety.watchdog_ms = 5000.0;  // the test thread commands slowly; the watchdog has its own tests
  }
  void TearDown() override {
    pen_.reset();
    fakes_.clear();
    if (testbed_) g_object_unref(testbed_);
  }
  FakeFalcon& addFalcon(int port, int devnum) {
    fakes_.push_back(std::make_unique<FakeFalcon>(testbed_, port, devnum));
    return *fakes_.back();
  }
  std::vector<uint8_t> writeFirmware(size_t size) {
    std::vector<uint8_t> image(size);
    for (size_t i = 0; i < size; ++i) image[i] = static_cast<uint8_t>(i * 37 + 11);
    options_.firmware_path = dir_ + "/falcon_firmware.bin";
    std::ofstream(options_.firmware_path, std::ios::binary).write(reinterpret_cast<const char*>(image.data()), image.size());
    return image;
  }
  // Opens falcon:0 against a fake with firmware running and all axes homed, and waits for Ready.
  void openReady(FakeFalcon& fake) {
    fake.setFirmwareRunning(true);
    fake.setHomed(7);
    pen_ = makeFalcon(0, options_);
    const Status s = pen_->open();
    ASSERT_TRUE(s.ok()) << s.message();
    ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Ready; }));
  }

  UMockdevTestbed* testbed_ = nullptr;
  std::string dir_;
  FalconOptions options_;
  std::vector<std::unique_ptr<FakeFalcon>> fakes_;
  std::unique_ptr<HapticDevice> pen_;
};

TEST_F(FalconUsb, EnumeratesInBusOrderWithoutClaiming) {
  FakeFalcon& late = addFalcon(4, 5);
  FakeFalcon& early = addFalcon(2, 3);
  const std::vector<DeviceEntry> found = enumerateFalcons();
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].name, "falcon:0");
  EXPECT_EQ(found[0].location, "usb 1-2 (/dev/bus/usb/001/003)");  // port 2 comes before port 4
  EXPECT_EQ(found[1].location, "usb 1-4 (/dev/bus/usb/001/005)");
  EXPECT_EQ(found[0].model, "Novint Falcon");
  EXPECT_EQ(found[0].kind, "pen");
  EXPECT_EQ(early.claims() + late.claims(), 0);
  EXPECT_TRUE(early.controls().empty());
}

TEST_F(FalconUsb, MissingFirmwareFileNamesThePath) {
  FakeFalcon& fake = addFalcon(4, 5);
  pen_ = makeFalcon(0, options_);
  const Status s = pen_->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(pen_->state(), DeviceState::NeedsFirmware);
  EXPECT_NE(pen_->reason().find(options_.firmware_path), std::string::npos) << pen_->reason();
  EXPECT_NE(s.message().find("falcon:0 (usb 1-4 (/dev/bus/usb/001/005))"), std::string::npos) << s.message();
  // It set the firmware mode and probed with one zero command, nothing more.
  EXPECT_EQ(fake.controls(), kFirmwareMode);
  EXPECT_EQ(fake.commands(), std::vector<std::string>{});  // no firmware: the fake took no packets
}

TEST_F(FalconUsb, LoadsFirmwareThenHomesThenRunsTheLoop) {
  FakeFalcon& fake = addFalcon(4, 5);
  const std::vector<uint8_t> image = writeFirmware(300);  // chunks of 128, 128, 44
  fake.setExpectedImage(image);
  fake.setEncoders(100, -200, 300);
  pen_ = makeFalcon(0, options_);
  const Status s = pen_->open();
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_TRUE(fake.firmwareRunning());
  EXPECT_EQ(fake.image(), image);
  // Probe in firmware mode, the loader handshake, then firmware mode again.
  const std::vector<ControlSetup> sent = fake.controls();
  const std::vector<ControlSetup> expected = concat({kFirmwareMode, kLoaderMode, kFirmwareMode});
  ASSERT_GE(sent.size(), expected.size());
  EXPECT_EQ(std::vector<ControlSetup>(sent.begin(), sent.begin() + expected.size()), expected);

  // Homing: red LED and the homing bit until the firmware reports all three axes.
  EXPECT_EQ(pen_->state(), DeviceState::NeedsHoming);
  EXPECT_NE(pen_->reason().find("not homed"), std::string::npos);
  ASSERT_TRUE(waitFor([&] { return fake.commandCount() > 3; }));
  EXPECT_EQ(fake.lastCommand(), kHomingCommand);
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));
  fake.setHomed(3);  // two of three: still homing
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  pen_->service();
  EXPECT_EQ(pen_->state(), DeviceState::NeedsHoming);
  fake.setHomed(7);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Ready; }));
  ASSERT_TRUE(waitFor([&] { return fake.lastCommand() == kHomedCommand; }));

  // The pose is the kinematics' forward solution of the encoders.
  ASSERT_TRUE(pen_->read(0.0, &r));
  falcon::Kinematics kin;
  const falcon::Angles angles = kin.anglesFromEncoders({100, -200, 300});
  Vec3 p;
  ASSERT_TRUE(kin.forward(angles, &p));
  EXPECT_NEAR(r.pose.position.x, p.x, 1e-6);
  EXPECT_NEAR(r.pose.position.y, p.y, 1e-6);
  EXPECT_NEAR(r.pose.position.z, p.z, 1e-6);

  // Steady loop: one command per status packet, so the commands keep coming. Counted, not timed:
  // how fast they come depends on the machine (a loaded one may stall the I/O thread for a while),
  // which is the benchmark's business; a loop that stopped never sends the next hundred.
  const size_t before = fake.commandCount();
  EXPECT_TRUE(waitFor([&] { return fake.commandCount() - before > 100; })) << fake.commandCount() - before;

  // Enabled: a small force (under the 0.5 N arming limit) goes out as the kinematics' motor words.
  ASSERT_TRUE(pen_->enable().ok());
  const Vec3 force{0.0, 0.0, 0.3};
  const falcon::Torques tau = kin.torquesForForce(angles, force);
  const std::array<int16_t, 3> words = kin.motorWords(tau);
  std::string expected_command = "<";
  for (int16_t w : words)
    for (int k = 0; k < 4; ++k) expected_command += static_cast<char>('A' + ((static_cast<uint16_t>(w) >> (4 * k)) & 0xF));
  expected_command += "EA>";  // blue LED (4) -> 'E'
  ASSERT_TRUE(waitFor([&] {
    pen_->command({force, {}}, std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch()).count());
    return fake.lastCommand() == expected_command;
  })) << fake.lastCommand() << " vs " << expected_command;

  // close(): the last packet on the wire carries zero force.
  pen_->close();
  EXPECT_EQ(fake.lastCommand(), kZeroCommand);
  EXPECT_EQ(pen_->state(), DeviceState::Disconnected);
  pen_->close();  // idempotent
}

TEST_F(FalconUsb, StallIsAFaultWithZeroForce) {
  FakeFalcon& fake = addFalcon(4, 5);
  openReady(fake);
  fake.setStall(true);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Fault; }));
  EXPECT_NE(pen_->reason().find("no data"), std::string::npos) << pen_->reason();
  EXPECT_EQ(fake.lastCommand(), kZeroCommand);
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));
  EXPECT_FALSE(pen_->enable().ok());
}

TEST_F(FalconUsb, WriteTimeoutIsAFault) {
  FakeFalcon& fake = addFalcon(4, 5);
  openReady(fake);
  fake.setHoldOut(true);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Fault; }));
  EXPECT_NE(pen_->reason().find("timed out"), std::string::npos) << pen_->reason();
}

TEST_F(FalconUsb, UnplugIsDisconnectedAndReplugHomesAgain) {
  FakeFalcon& fake = addFalcon(4, 5);
  writeFirmware(200);
  fake.setExpectedImage(std::vector<uint8_t>());  // first open finds the firmware running
  openReady(fake);
  fake.setGone(true);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Disconnected; }));
  EXPECT_NE(pen_->reason().find("unplugged"), std::string::npos) << pen_->reason();
  DeviceReading r;
  EXPECT_FALSE(pen_->read(0.0, &r));
  // Replugged: no firmware, not homed. service() finds it, loads the firmware and homes again.
  std::vector<uint8_t> image(200);
  for (size_t i = 0; i < image.size(); ++i) image[i] = static_cast<uint8_t>(i * 37 + 11);
  fake.setExpectedImage(image);
  fake.setHomed(0);
  fake.setGone(false);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::NeedsHoming; }))
      << stateName(pen_->state()) << ": " << pen_->reason();
  EXPECT_TRUE(fake.firmwareRunning());
  fake.setHomed(7);
  ASSERT_TRUE(waitFor([&] { pen_->service(); return pen_->state() == DeviceState::Ready; }));
}

}  // namespace
}  // namespace dentsim::devices
