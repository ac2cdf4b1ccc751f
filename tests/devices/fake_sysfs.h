// A fake sysfs tree and /dev under a temporary folder, for the tests of what dentsim finds out from sysfs about a Touch pen's serial node.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"
#include "unprivileged.h"

namespace dentsim::test {

// A sysfs tree and a /dev under one temporary folder, laid out as the kernel lays them out: each
// tty's folder sits under its USB interface, under its USB device (the one with idVendor), and
// class/tty/NAME links to it.
class FakeSys {
 public:
  FakeSys() {
    letEveryoneIn(dir_.path());
    std::filesystem::create_directories(sys() / "class" / "tty");
    std::filesystem::create_directories(dev());
  }
  std::filesystem::path sys() const { return dir_.path() / "sys"; }
  std::filesystem::path dev() const { return dir_.path() / "dev"; }

  // A CDC ACM tty NAME on a USB device with this vendor id, at USB port `port` of bus 1.
  void addUsbTty(const std::string& name, const std::string& vendor_hex, int port) {
    const std::filesystem::path usb = sys() / "devices/pci0000:00/0000:00:14.0/usb1" / ("1-" + std::to_string(port));
    std::filesystem::create_directories(usb);
    std::ofstream(usb / "idVendor") << vendor_hex << "\n";
    std::ofstream(usb / "idProduct") << "0302\n";
    addTty(name, usb / ("1-" + std::to_string(port) + ":1.0") / "tty" / name);
  }
  // A tty with no USB ancestor, as a UART's: devices/platform/serial8250/tty/NAME.
  void addPlatformTty(const std::string& name) { addTty(name, sys() / "devices/platform/serial8250/tty" / name); }

  // The node /dev/NAME as a plain file with `mode`: access() judges it as it judges a device node.
  std::filesystem::path addNode(const std::string& name, std::filesystem::perms mode) {
    const std::filesystem::path node = dev() / name;
    std::ofstream(node).close();
    std::filesystem::permissions(node, mode, std::filesystem::perm_options::replace);
    return node;
  }

 private:
  void addTty(const std::string& name, const std::filesystem::path& folder) {
    std::filesystem::create_directories(folder);
    std::ofstream(folder / "dev") << "166:0\n";
    // Relative, as the kernel's: class/tty/NAME -> ../../devices/...
    std::filesystem::create_directory_symlink(std::filesystem::relative(folder, sys() / "class" / "tty"), sys() / "class" / "tty" / name);
  }
  TempDir dir_;
};

}  // namespace dentsim::test
