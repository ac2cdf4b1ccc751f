// Tests for devices/70-dentsim.rules: every node whose permission line names the file has a rule in it, matched the way its backend finds the device.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "devices/hid_pedal.h"
#include "devices/touch_serial.h"

namespace dentsim::devices {
namespace {

// The rule lines in force: not blank, not commented out.
std::vector<std::string> activeRules() {
  std::ifstream in(std::string(DENTSIM_SOURCE_DIR) + "/devices/70-dentsim.rules");
  std::vector<std::string> rules;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') rules.push_back(line);
  return rules;
}

std::string hex4(uint16_t v) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", v);
  return text;
}

// The one rule that holds every one of `parts`; fails the test unless there is exactly one.
std::string ruleWith(const std::vector<std::string>& rules, const std::vector<std::string>& parts) {
  std::vector<std::string> hits;
  for (const std::string& rule : rules) {
    bool all = true;
    for (const std::string& p : parts) all = all && rule.find(p) != std::string::npos;
    if (all) hits.push_back(rule);
  }
  std::string wanted;
  for (const std::string& p : parts) wanted += p + " ";
  EXPECT_EQ(hits.size(), 1u) << "rules holding " << wanted;
  return hits.empty() ? std::string() : hits[0];
}

TEST(UdevRules, EveryDeviceThatNamesTheFileHasItsRule) {
  const std::vector<std::string> rules = activeRules();
  ASSERT_FALSE(rules.empty()) << DENTSIM_SOURCE_DIR;
  // The Falcon: libusb opens the USB device node.
  ruleWith(rules, {"SUBSYSTEM==\"usb\"", "ENV{DEVTYPE}==\"usb_device\"", "ATTR{idVendor}==\"0403\"",
                   "ATTR{idProduct}==\"cb48\""});
  // Each known pedal: hidapi opens its hidraw node, whose USB ancestor carries the ids.
  for (const KnownPedal& p : knownPedals())
    ruleWith(rules, {"KERNEL==\"hidraw*\"", "SUBSYSTEM==\"hidraw\"", "ATTRS{idVendor}==\"" + hex4(p.vendor_id) + "\"",
                     "ATTRS{idProduct}==\"" + hex4(p.product_id) + "\""});
  // The Touch: the same vendor id that touchSerialNodes() looks for, on the ACM tty.
  ruleWith(rules, {"KERNEL==\"ttyACM*\"", "SUBSYSTEM==\"tty\"",
                   "ATTRS{idVendor}==\"" + hex4(kTouchUsbVendorId) + "\""});
  // The haptic loop's idle-latency request.
  ruleWith(rules, {"KERNEL==\"cpu_dma_latency\"", "SUBSYSTEM==\"misc\""});
}

TEST(UdevRules, EveryRuleOpensTheNodeToTheSeatAndToPlugdev) {
  // What docs/DEVICES.md promises: the user at the seat (uaccess) and group plugdev, no one else.
  for (const std::string& rule : activeRules()) {
    EXPECT_NE(rule.find("TAG+=\"uaccess\""), std::string::npos) << rule;
    EXPECT_NE(rule.find("GROUP=\"plugdev\""), std::string::npos) << rule;
    EXPECT_NE(rule.find("MODE=\"0660\""), std::string::npos) << rule;
  }
}

}  // namespace
}  // namespace dentsim::devices
