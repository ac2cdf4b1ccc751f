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
};

// The configured pens HDAPI can open ("openhaptics:Default", ...). Without the library, one entry
// saying it is not installed (or none when there is nothing to say).
std::vector<DeviceEntry> enumerateOpenHaptics(const OpenHapticsOptions& options = {});

// The pen HDAPI knows by `device_name` ("Default" is HD_DEFAULT_DEVICE), not opened yet.
std::unique_ptr<HapticDevice> makeOpenHapticsPen(const std::string& device_name,
                                                 const OpenHapticsOptions& options = {});

}  // namespace dentsim::devices
