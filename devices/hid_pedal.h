// USB HID foot pedals through hidapi: on/off switches and proportional pedals with an axis.
//
// Entry points first: enumerateHidPedals() lists what `--pedal hid:...` can take, makeHidPedal()
// builds one from its spec. Below them: the spec grammar and the table of known pedals. The report
// layouts and their decoder (pure functions) are in hid_pedal_descriptor.h, the HID transport the
// pedal reads through (hidapi by default, a fake in the tests) in hid_pedal_transport.h.
//
// Spec (what follows "hid:"; a leading "hid:" is accepted too), a target then options by commas:
//   N                 the N-th pedal enumerateHidPedals() lists ("hid:0")
//   VVVV:PPPP         USB vendor:product in hex ("hid:0c45:7403")
//   /dev/hidrawN      a hidraw node
//   button=B:b        a switch: bit b [0, 7] of report byte B; pressed = 1
//   axis=B[.b]:N:MIN:MAX   a proportional axis: N bits [1, 32] from bit b of byte B, little-endian,
//                     raw MIN at rest and MAX fully down (MIN < 0 or MAX < 0: a signed field)
//   key[=CODE]        a keyboard sold as a foot switch: any key (or usage CODE) down = 1
//   invert            1 at rest, 0 pressed (normally-closed switches, pedals wired backwards)
//   deadband=F        positions below F [0, 0.5) read 0, so a pedal at rest never creeps the turbine
//   report=ID         only reports whose first byte (the report id) is ID count
//   serial=S          the one with this serial number, where several alike are plugged in
// Byte offsets count from the first byte hidapi returns, which is the report id where the device
// numbers its reports. Without button/axis/key the layout comes from the known-pedal table, else
// from the device's HID report descriptor (Simulation Controls accelerator/brake, a Generic Desktop
// axis, or the first button).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "devices/device_entry.h"
#include "devices/foot_pedal.h"
#include "devices/hid_pedal_descriptor.h"
#include "devices/hid_pedal_transport.h"

namespace dentsim::devices {

struct HidPedalOptions {
  int read_timeout_ms = 10;         // one hid_read_timeout: how long an unplug can go unseen [ms]
  int reconnect_interval_ms = 500;  // service() looks for a replugged pedal at most this often [ms]
};

// Every HID device that looks like a foot pedal (a known model, a name saying pedal or foot switch,
// or Simulation Controls usage), as "hid:0", "hid:1", ... in enumeration order.
std::vector<DeviceEntry> enumerateHidPedals();
std::vector<DeviceEntry> enumerateHidPedals(HidTransport& transport);

// The pedal `spec` names (what follows "hid:" in --pedal), not opened yet. A bad spec is a one-line
// error naming it ("hid:0c45:74zz: bad vendor:product ...").
Result<std::unique_ptr<FootPedal>> makeHidPedal(const std::string& spec);
Result<std::unique_ptr<FootPedal>> makeHidPedal(const std::string& spec, std::shared_ptr<HidTransport> transport,
                                                const HidPedalOptions& options = {});

// ---- spec ----

struct HidPedalSpec {
  enum class Target : uint8_t { Index, VendorProduct, Path };
  std::string text;                 // as given, with "hid:" in front
  Target target = Target::Index;
  int index = 0;                    // Index: among enumerateHidPedals()
  uint16_t vendor_id = 0;           // VendorProduct
  uint16_t product_id = 0;
  std::string path;                 // Path: "/dev/hidraw3"
  std::string serial;               // empty: any
  std::optional<PedalLayout> layout;  // button/axis/key given; otherwise the table or the descriptor
  std::optional<bool> invert;         // options that adjust whichever layout is used
  std::optional<double> dead_band;
  std::optional<int> report_id;
};

Result<HidPedalSpec> parseHidPedalSpec(const std::string& spec);

// ---- known pedals ----

struct KnownPedal {
  uint16_t vendor_id;
  uint16_t product_id;
  const char* model;
  uint16_t usage_page;  // the interface that carries the pedal (0: any)
  uint16_t usage;
  PedalLayout layout;
};

std::span<const KnownPedal> knownPedals();

}  // namespace dentsim::devices
