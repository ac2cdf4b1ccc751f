// The device handler: what --drill, --mirror and --pedal name, the backend that opens it, and the list of what is connected.
//
// Pen names: "virtual" (the mouse and keys), "script:FILE" (a pen path), "replay:FILE" (a recorded
// session's pen), "falcon" or "falcon:N" (the N-th Novint Falcon on the USB bus), "openhaptics" or
// "openhaptics:NAME" (an HDAPI device name; "Default" is the vendor's default device).
// Pedal names: "none", "hid" or "hid:SPEC" (see hid_pedal.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "devices/device_entry.h"
#include "devices/device_options.h"
#include "devices/foot_pedal.h"
#include "devices/haptic_device.h"
#include "io/pen_path_file.h"

namespace dentsim::devices {

struct PenName {
  std::string backend;  // "virtual", "script", "replay", "falcon", "openhaptics"
  std::string arg;      // the file, the index or the device name; may be empty
  std::string text;     // as given
  bool software() const { return backend == "virtual" || backend == "script" || backend == "replay"; }
};
// One-line error naming the text and the choices when it is not a pen name.
Result<PenName> parsePenName(const std::string& text);

// What a software pen needs from the program.
struct PenContext {
  PenRole role = PenRole::Drill;
  Pose start_grip;               // where the virtual pen starts [mm], world
  double max_force_n = 8.0;      // the parameter set's limits, which software pens take as their spec
  double max_torque_n_mm = 0.0;
  DeviceOptions options;         // the backends' options (the Falcon's firmware, ...)
};

// The pen `name` names, made but not opened (the caller opens it and reports its state).
Result<std::unique_ptr<HapticDevice>> makePen(const PenName& name, const PenContext& context);
// One-line error unless `name` is a pedal name ("none", "hid", "hid:SPEC"); the SPEC itself is
// checked when the pedal is made.
Status checkPedalName(const std::string& name);
// The pedal `name` names, made but not opened; null for "none".
Result<std::unique_ptr<FootPedal>> makePedal(const std::string& name);

// Every pen and pedal found, software pens first, each with its state and why it cannot be used.
std::vector<DeviceEntry> listDevices(const PenContext& context = {});

}  // namespace dentsim::devices
