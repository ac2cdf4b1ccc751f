// The Novint Falcon over libusb-1.0: enumeration and the pen backend, written from the Falcon's public protocol.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/device_entry.h"
#include "devices/haptic_device.h"

namespace dentsim::devices {

struct FalconOptions {
  // The firmware image to load when the Falcon has none running. dentsim never ships it: the user
  // supplies it. Empty: $DENTSIM_FALCON_FIRMWARE, else $XDG_CONFIG_HOME/dentsim/falcon_firmware.bin.
  std::string firmware_path;
  SafetyParams safety;
};

// Every Falcon on the USB bus, in bus order ("falcon:0", "falcon:1", ...), with its state as far as
// it can be told without taking it over, and why it cannot be used (permissions, firmware missing).
std::vector<DeviceEntry> enumerateFalcons();

// The index-th Falcon, not opened yet: open() claims it, loads the firmware if needed and starts
// the asynchronous I/O; the state then says whether homing is needed.
std::unique_ptr<HapticDevice> makeFalcon(int index, const FalconOptions& options = {});

}  // namespace dentsim::devices
