// Tests for devices/touch_serial.h: Touch ttys found by the vendor id of their USB parent in a fake sysfs tree, and the permission line for a node the unprivileged user nobody may not open.
#include "devices/touch_serial.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/permission_advice.h"
#include "devices/fake_sysfs.h"
#include "test_support.h"
#include "unprivileged.h"

namespace dentsim::devices {
namespace {

namespace fs = std::filesystem;

using test::FakeSys;

TEST(TouchSerial, FindsTheTtysOfTouchPensByTheirUsbVendorInNaturalOrder) {
  FakeSys fake;
  fake.addUsbTty("ttyACM0", "2341", 1);  // another ACM device (a microcontroller board): not a Touch
  fake.addUsbTty("ttyACM1", "2988", 2);
  fake.addUsbTty("ttyACM10", "2988", 4);
  fake.addUsbTty("ttyACM2", "2988", 3);
  fake.addPlatformTty("ttyS0");  // no USB parent at all
  const std::string dev = fake.dev().string();
  // ttyACM2 before ttyACM10; the nodes need not exist to be found.
  EXPECT_EQ(touchSerialNodes(fake.sys().string(), dev),
            (std::vector<std::string>{dev + "/ttyACM1", dev + "/ttyACM2", dev + "/ttyACM10"}));
}

TEST(TouchSerial, NoTtyFolderOrNoTouchFindsNothing) {
  const test::TempDir empty;
  EXPECT_TRUE(touchSerialNodes(empty.path().string(), "/dev").empty());
  EXPECT_TRUE(touchSerialNodes((empty.path() / "missing").string(), "/dev").empty());
  EXPECT_EQ(touchSerialPermissionProblem(empty.path().string(), "/dev"), "");

  FakeSys fake;
  fake.addUsbTty("ttyACM0", "2341", 1);
  fake.addNode("ttyACM0", fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_TRUE(touchSerialNodes(fake.sys().string(), fake.dev().string()).empty());
}

TEST(TouchSerial, NamesTheFirstTouchNodeNobodyMayNotOpen) {
  if (const std::string why = test::whyNotNobody(); !why.empty()) GTEST_SKIP() << why;
  FakeSys fake;
  const auto root_only = fs::perms::owner_read | fs::perms::owner_write;  // 0600, owned by root
  const auto everyone = root_only | fs::perms::group_read | fs::perms::group_write | fs::perms::others_read |
                        fs::perms::others_write;  // 0666, what the udev rule's ACL amounts to
  fake.addUsbTty("ttyACM0", "2341", 1);
  fake.addNode("ttyACM0", root_only);  // not a Touch: not reported, however closed
  fake.addUsbTty("ttyACM1", "2988", 2);
  fake.addNode("ttyACM1", everyone);
  fake.addUsbTty("ttyACM2", "2988", 3);  // a Touch whose node is gone (unplugged): skipped
  fake.addUsbTty("ttyACM10", "2988", 4);
  const fs::path closed = fake.addNode("ttyACM10", root_only);
  const std::string sys = fake.sys().string(), dev = fake.dev().string();

  // Root opens anything, so root sees no problem; nobody is refused ttyACM10 and told why.
  EXPECT_EQ(touchSerialPermissionProblem(sys, dev), "");
  const std::string line = test::inChildAsNobody([&] { return touchSerialPermissionProblem(sys, dev); });
  EXPECT_EQ(line, permissionAdvice(closed.string()));
  EXPECT_NE(line.find("devices/70-dentsim.rules"), std::string::npos) << line;

  // Once the node is open to everyone, as after the rule and a replug, nobody has no problem.
  fs::permissions(closed, everyone, fs::perm_options::replace);
  EXPECT_EQ(test::inChildAsNobody([&] { return touchSerialPermissionProblem(sys, dev); }), "");
}

}  // namespace
}  // namespace dentsim::devices
