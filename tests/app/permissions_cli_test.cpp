// Permission paths end to end: the real dentsim, run as the unprivileged user nobody, meets a Falcon, a pedal and /dev/cpu_dma_latency it may not open, and says so in one line that names the udev rule.
//
// The tests run as root, which every file mode lets in, so each case runs the binary through
// setpriv as nobody. The Falcon and the pedal are umockdev testbeds (umockdev-run, as in
// tests/devices_usb): the testbed is made by nobody, so nobody owns its node, and mode 000 is what
// a root-owned 0600 node is to a user without the rule. /dev/cpu_dma_latency is the real one,
// root's 0600 where the rule is not installed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/permission_advice.h"
#include "test_json.h"
#include "test_support.h"
#include "unprivileged.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::runCommand;
using test::TempDir;

// A Falcon (FTDI 0403:cb48) at usb 1-2, node /dev/bus/usb/001/002, in umockdev's description format.
constexpr const char* kFalconTestbed =
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-2\n"
    "N: bus/usb/001/002\n"
    "E: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\nE: DRIVER=usb\n"
    "E: BUSNUM=001\nE: DEVNUM=002\nE: DEVNAME=/dev/bus/usb/001/002\n"
    "A: busnum=1\\n\nA: devnum=2\\n\nA: bConfigurationValue=1\\n\nA: speed=12\\n\n"
    "A: idVendor=0403\\n\nA: idProduct=cb48\\n\n"
    // Device descriptor, one configuration, one vendor interface with bulk endpoints 0x81 and 0x02.
    "H: descriptors=1201000200000008030448cb0006010203010902200001010080"
    "2d0904000002ffffff020705810240000007050202400000\n";

// A VEC Infinity pedal (05f3:00ff, a known pedal whose layout needs no report descriptor) at usb
// 1-3: its hidraw node /dev/hidraw0 under the HID device, the USB interface and the USB device.
constexpr const char* kPedalTestbed =
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-3/1-3:1.0/0003:05F3:00FF.0001/hidraw/hidraw0\n"
    "N: hidraw0\nE: SUBSYSTEM=hidraw\nE: DEVNAME=/dev/hidraw0\n\n"
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-3/1-3:1.0/0003:05F3:00FF.0001\n"
    "E: SUBSYSTEM=hid\nE: DRIVER=hid-generic\nE: HID_ID=0003:000005F3:000000FF\n"
    "E: HID_NAME=VEC VEC USB Footpedal\nE: HID_PHYS=usb-0000:00:14.0-3/input0\nE: HID_UNIQ=\n\n"
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-3/1-3:1.0\n"
    "E: SUBSYSTEM=usb\nE: DEVTYPE=usb_interface\nE: DRIVER=usbhid\nA: bInterfaceNumber=00\\n\n\n"
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-3\n"
    "E: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\nE: DRIVER=usb\n"
    "A: idVendor=05f3\\n\nA: idProduct=00ff\\n\nA: manufacturer=VEC\\n\nA: product=VEC USB Footpedal\\n\n";

constexpr const char* kQos = "/dev/cpu_dma_latency";

// The line for a refused idle-latency request (src/sim/idle_latency.cpp).
std::string refusedQosLine() {
  return permissionAdvice(kQos, RuleTakesEffect::Trigger) + "; optional: the loop runs without it, with slower steps after idle";
}

class PermissionsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::whyNotNobody(); !why.empty()) GTEST_SKIP() << why;
    if (!test::haveSetpriv()) GTEST_SKIP() << "setpriv is not installed (Debian: util-linux; scripts/install-deps.sh)";
    test::letEveryoneIn(dir_.path());
    binary_ = binaryNobodyRuns();
  }

  // The dentsim binary where nobody may run it. A build under a folder nobody may not enter (a
  // checkout in /root) gets a copy in this test's folder; its libraries are the system's (ldd).
  std::string binaryNobodyRuns() {
    const std::string built = DENTSIM_BINARY;
    if (runCommand(test::asNobody() + "test -x '" + built + "'").exit_code == 0) return built;
    const fs::path copy = dir_.path() / "dentsim";
    fs::copy_file(built, copy, fs::copy_options::overwrite_existing);
    fs::permissions(copy, fs::perms(0755), fs::perm_options::replace);
    return copy.string();
  }

  // `dentsim devices --json` as nobody inside a umockdev testbed described by `testbed`, with the
  // testbed's `node` (relative to /dev) first made mode `mode`.
  test::CommandResult devicesAsNobody(const std::string& testbed, const std::string& node, const char* mode) {
    const std::string file = dir_.file("testbed.umockdev");
    std::ofstream(file) << testbed;
    fs::permissions(file, fs::perms(0644), fs::perm_options::replace);
    // umockdev-run preloads its library ahead of the sanitizer's runtime, which ASan refuses by
    // default: the sanitizer build lets that order be (as the devices_usb suite does).
    return runCommand(test::asNobody() + "env ASAN_OPTIONS=\"${ASAN_OPTIONS}:verify_asan_link_order=0\" umockdev-run -d '" + file + "' -- sh -c 'chmod " + mode +
                      " \"$UMOCKDEV_DIR/dev/" + node + "\" && exec \"$0\" devices --json' '" + binary_ + "'");
  }

  // The entry named `name` in `dentsim devices --json`'s output; null when absent.
  static nlohmann::json entry(const std::string& output, const std::string& name) {
    const size_t start = output.find('[');
    if (start == std::string::npos) return nullptr;
    const nlohmann::json all = nlohmann::json::parse(output.substr(start), nullptr, false);
    if (!all.is_array()) return nullptr;
    for (const nlohmann::json& e : all)
      if (e.value("name", "") == name) return e;
    return nullptr;
  }

  static bool haveUmockdev() { return std::system("command -v umockdev-run >/dev/null 2>&1") == 0; }

  TempDir dir_;
  std::string binary_;
};

TEST_F(PermissionsCli, AFalconNobodyMayNotOpenNamesTheRule) {
  if (!haveUmockdev()) GTEST_SKIP() << "umockdev-run is not installed (Debian: umockdev)";
  const auto closed = devicesAsNobody(kFalconTestbed, "bus/usb/001/002", "000");
  ASSERT_EQ(closed.exit_code, 0) << closed.output;  // listing is not failing: the entry says why
  const nlohmann::json falcon = entry(closed.output, "falcon:0");
  ASSERT_TRUE(falcon.is_object()) << closed.output;
  EXPECT_EQ(falcon["usable"], false);
  EXPECT_EQ(falcon["state"], "disconnected");
  EXPECT_EQ(falcon["reason"], permissionAdvice("/dev/bus/usb/001/002"));

  // The same Falcon with its node open to nobody: no permission line, so the line above came from
  // the mode and nothing else.
  const auto open = devicesAsNobody(kFalconTestbed, "bus/usb/001/002", "666");
  ASSERT_EQ(open.exit_code, 0) << open.output;
  const nlohmann::json usable = entry(open.output, "falcon:0");
  ASSERT_TRUE(usable.is_object()) << open.output;
  EXPECT_EQ(usable["reason"].get<std::string>().find("permission denied"), std::string::npos) << open.output;
  EXPECT_NE(usable["state"], "disconnected") << open.output;
}

TEST_F(PermissionsCli, APedalNobodyMayNotOpenNamesTheRule) {
  if (!haveUmockdev()) GTEST_SKIP() << "umockdev-run is not installed (Debian: umockdev)";
  const auto closed = devicesAsNobody(kPedalTestbed, "hidraw0", "000");
  ASSERT_EQ(closed.exit_code, 0) << closed.output;
  const nlohmann::json pedal = entry(closed.output, "hid:0");
  ASSERT_TRUE(pedal.is_object()) << closed.output;
  EXPECT_EQ(pedal["usable"], false);
  EXPECT_EQ(pedal["reason"], permissionAdvice("/dev/hidraw0"));

  const auto open = devicesAsNobody(kPedalTestbed, "hidraw0", "666");
  ASSERT_EQ(open.exit_code, 0) << open.output;
  const nlohmann::json usable = entry(open.output, "hid:0");
  ASSERT_TRUE(usable.is_object()) << open.output;
  EXPECT_EQ(usable["usable"], true) << open.output;
  EXPECT_EQ(usable["state"], "ready");
}

// Why the real /dev/cpu_dma_latency cannot show nobody's refusal here, or empty when it can.
std::string whyNoRefusedQos() {
  if (!fs::exists(kQos)) return std::string(kQos) + " does not exist here";
  if (runCommand(test::asNobody() + "test -w " + kQos).exit_code == 0)
    return std::string("nobody may already write ") + kQos + " here (the udev rule is installed)";
  return {};
}

TEST_F(PermissionsCli, TheIdleLatencyRequestNobodyMayNotOpenIsOptionalAndNamesTheRule) {
  if (const std::string why = whyNoRefusedQos(); !why.empty()) GTEST_SKIP() << why;
  // The haptic bench's loop thread asks for the request, as `dentsim run`'s does; the shortest run.
  const fs::path out = dir_.path() / "out";
  fs::create_directory(out);
  fs::permissions(out, fs::perms(0777), fs::perm_options::replace);
  const auto r = runCommand("cd '" + dir_.path().string() + "' && " + test::asNobody() + "'" + binary_ +
                            "' bench haptic --cpu-voxelize --levels 5 --laps 0.05 --no-step-only --no-after-idle "
                            "--out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;  // optional: the loop ran without it
  const std::string line = refusedQosLine();
  EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
  const nlohmann::json report = test::readJson((out / "haptic.json").string());
  ASSERT_FALSE(report.is_discarded()) << r.output;
  EXPECT_EQ(report["levels"][0]["thread"]["idle_latency"]["held"], false);
  EXPECT_EQ(report["levels"][0]["thread"]["idle_latency"]["note"], line);
}

TEST_F(PermissionsCli, RunSaysOnceThatTheIdleLatencyRequestWasRefused) {
  if (const std::string why = whyNoRefusedQos(); !why.empty()) GTEST_SKIP() << why;
  if (!test::haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  // In a window the loop runs on its own thread, which asks for the request; headless would step it
  // in lockstep and never ask. The X server is nobody's too; home is a folder nobody may write.
  const fs::path home_dir = dir_.path() / "home";
  fs::create_directory(home_dir);
  fs::permissions(home_dir, fs::perms(0777), fs::perm_options::replace);
  const std::string home = home_dir.string();
  const test::NoLeakCheckForGpuChild no_leak_check;  // the run drives lavapipe (test_support.h)
  const auto r = runCommand("cd '" + home + "' && " + test::asNobody() + "env HOME='" + home + "' XDG_CACHE_HOME='" +
                            home + "' xvfb-run -a -s '-screen 0 640x480x24' '" + binary_ +
                            "' run --level 6 --exit-after 0.3 --no-sound --width 320 --height 240");
  ASSERT_EQ(r.exit_code, 0) << r.output;  // optional: the run went on without it
  const std::string line = "dentsim: " + refusedQosLine() + "\n";
  const size_t first = r.output.find(line);
  ASSERT_NE(first, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(line, first + 1), std::string::npos) << "said more than once: " << r.output;
}

}  // namespace
}  // namespace dentsim
