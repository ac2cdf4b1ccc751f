// DeviceOptions: every user option of the pens' backends in one struct, which the app fills from its flags and hands on whole.
//
// A new backend's option goes here and into the registry that reads it, so the app's flags, the
// simulator and `dentsim devices` pass one value instead of threading each option through.
#pragma once

#include "devices/falcon_device.h"
#include "devices/openhaptics_pen.h"

namespace dentsim::devices {

struct DeviceOptions {
  FalconOptions falcon;            // the Falcon's firmware file and safety limits
  OpenHapticsOptions openhaptics;  // the HDAPI library and safety limits
  double reach_mm = 40.0;          // a hardware pen's workspace spans this much of the scene [mm], > 0
};

}  // namespace dentsim::devices
