// OpenHaptics plug-in: Touch, Omni and Touch X pens through the vendor's HDAPI, loaded with dlopen only when it is present.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/device_entry.h"
#include "devices/haptic_device.h"

namespace dentsim::devices {

struct OpenHapticsOptions {
  // The HDAPI library to load. Empty: $DENTSIM_OPENHAPTICS_LIB, else "libHD.so" through the
  // dynamic loader's usual search. dentsim's build never needs it.
  std::string library;
  SafetyParams safety;
  // Where a failed open looks for a Touch's serial node the user may not open (touch_serial.h);
  // the tests point them at a fake tree.
  std::string sysfs_root = "/sys";
  std::string dev_root = "/dev";
};

// The names of the configured pens: one per NAME.config in $GTDD_HOME/config (default
// /usr/share/3DSystems/config), "Default Device" given as "Default"; sorted. Empty: no folder.
std::vector<std::string> configuredOpenHapticsNames();

// Every configured pen HDAPI can open ("openhaptics:Left", "openhaptics:Right", ...; only
// "openhaptics:Default" without a configuration folder), each probed briefly for its model,
// serial and calibration. Without the library, the same entries saying it is not installed.
std::vector<DeviceEntry> enumerateOpenHaptics(const OpenHapticsOptions& options = {});

// The pen HDAPI knows by `device_name` ("Default" is HD_DEFAULT_DEVICE), not opened yet.
std::unique_ptr<HapticDevice> makeOpenHapticsPen(const std::string& device_name,
                                                 const OpenHapticsOptions& options = {});

}  // namespace dentsim::devices
