// DeviceEntry: one line of `dentsim devices`: a pen or pedal that was found, its state, and why it cannot be used.
#pragma once

#include <string>

#include "devices/haptic_device.h"

namespace dentsim::devices {

struct DeviceEntry {
  std::string name;      // what --drill, --mirror or --pedal takes: "falcon:0", "openhaptics:Default", "hid:0"
  std::string kind;      // "pen" or "pedal"
  std::string model;     // "Novint Falcon", "Touch", "USB foot pedal (proportional)"
  std::string location;  // where it was found: "usb 1-4 (/dev/bus/usb/001/004)", "/dev/hidraw3", a library path
  DeviceState state = DeviceState::Disconnected;  // as far as could be told without taking it over
  std::string reason;    // why it cannot be used as it is (permissions, firmware missing, not homed); empty if usable
};

}  // namespace dentsim::devices
