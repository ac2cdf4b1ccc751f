// Tests for devices/touch_serial.h: Touch ttys found by the vendor id of their USB parent in a fake sysfs tree, and the permission line for a node the unprivileged user nobody may not open.
#include "devices/touch_serial.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/permission_advice.h"
#include "test_support.h"
#include "unprivileged.h"

namespace dentsim::devices {
namespace {

namespace fs = std::filesystem;

// A sysfs tree and a /dev under one temporary folder, laid out as the kernel lays them out: each
// tty's folder sits under its USB interface, under its USB device (the one with idVendor), and
// class/tty/NAME links to it.
class FakeSys {
 public:
  FakeSys() {
    test::letEveryoneIn(dir_.path());
    fs::create_directories(sys() / "class" / "tty");
    fs::create_directories(dev());
  }
  fs::path sys() const { return dir_.path() / "sys"; }
  fs::path dev() const { return dir_.path() / "dev"; }

  // A CDC ACM tty NAME on a USB device with this vendor id, at USB port `port` of bus 1.
  void addUsbTty(const std::string& name, const std::string& vendor_hex, int port) {
    const fs::path usb = sys() / "devices/pci0000:00/0000:00:14.0/usb1" / ("1-" + std::to_string(port));
    fs::create_directories(usb);
    std::ofstream(usb / "idVendor") << vendor_hex << "\n";
    std::ofstream(usb / "idProduct") << "0302\n";
    addTty(name, usb / ("1-" + std::to_string(port) + ":1.0") / "tty" / name);
  }
  // A tty with no USB ancestor, as a UART's: devices/platform/serial8250/tty/NAME.
  void addPlatformTty(const std::string& name) { addTty(name, sys() / "devices/platform/serial8250/tty" / name); }

  // The node /dev/NAME as a plain file with `mode`: access() judges it as it judges a device node.
  fs::path addNode(const std::string& name, fs::perms mode) {
    const fs::path node = dev() / name;
    std::ofstream(node).close();
    fs::permissions(node, mode, fs::perm_options::replace);
    return node;
  }

 private:
  void addTty(const std::string& name, const fs::path& folder) {
    fs::create_directories(folder);
    std::ofstream(folder / "dev") << "166:0\n";
    // Relative, as the kernel's: class/tty/NAME -> ../../devices/...
    fs::create_directory_symlink(fs::relative(folder, sys() / "class" / "tty"), sys() / "class" / "tty" / name);
  }
  test::TempDir dir_;
};

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
