// USB HID foot pedals through hidapi: on/off switches and proportional pedals with an axis.
//
// Entry points first: enumerateHidPedals() lists what `--pedal hid:...` can take, makeHidPedal()
// builds one from its spec. Below them: the spec grammar, the report layouts and their decoder (pure
// functions), the table of known pedals, and the HID transport the pedal reads through (hidapi by
// default, a fake in the tests).
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

namespace dentsim::devices {

class HidTransport;

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

// ---- report layouts ----

enum class PedalInput : uint8_t {
  Button,  // one or more bits: any set = pressed = 1
  Axis,    // an N-bit field mapped linearly to [0, 1]
  Key,     // a boot-protocol keyboard report: modifiers, reserved, six key usages
};

struct PedalLayout {
  PedalInput input = PedalInput::Button;
  int report_id = -1;        // the report's first byte must be this [0, 255]; -1: every report counts
  int byte = 0;              // Button, Axis: byte offset in the report as hidapi returns it
  int bit = 0;               // Axis: first bit within that byte [0, 7] (LSB = 0)
  uint8_t button_mask = 1;   // Button: the bits of `byte` that are pedals
  int bits = 8;              // Axis: field width [1, 32]
  int64_t raw_min = 0;       // Axis: raw value at rest
  int64_t raw_max = 255;     // Axis: raw value fully pressed
  uint8_t key_code = 0;      // Key: the HID keyboard usage that means pressed; 0: any key or modifier
  bool invert = false;       // the position is 1 - decoded
  double dead_band = 0.02;   // positions below this read 0 [0, 0.5)
};

// "axis byte 1 bit 0, 8 bits, raw 0..255", for `dentsim devices` and error messages.
std::string describeLayout(const PedalLayout& layout);

// The pedal position [0, 1] one input report carries; nullopt where the report is not for the pedal
// (another report id) or too short to hold the field. Never reads past report.size().
std::optional<double> decodePedalReport(const PedalLayout& layout, std::span<const uint8_t> report);

// The pedal input a HID report descriptor declares: a Simulation Controls accelerator or brake, else
// a Generic Desktop axis (X..Slider), else the first button; nullopt when it has none of them or the
// descriptor is malformed.
std::optional<PedalLayout> layoutFromReportDescriptor(std::span<const uint8_t> descriptor);

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

// ---- transport: open by path, enumerate, read with a timeout, close (the destructor) ----

struct HidDeviceInfo {
  std::string path;              // "/dev/hidraw3"
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string serial;
  std::string manufacturer;
  std::string product;
  uint16_t usage_page = 0;       // of the top-level collection
  uint16_t usage = 0;
  int interface_number = -1;
  bool permitted = true;         // the node may be opened for reading and writing by this user
};

// One open device. read() and the destructor are called from one thread at a time.
class HidConnection {
 public:
  virtual ~HidConnection() = default;
  // Waits at most timeout_ms for one input report: its size (> 0; only `capacity` bytes are stored),
  // 0 when none came, < 0 when the device failed or is gone (error() says why).
  virtual int read(uint8_t* buffer, size_t capacity, int timeout_ms) = 0;
  virtual std::string error() const = 0;
};

enum class HidOpenError : uint8_t { None, NotFound, PermissionDenied, Failed };

struct HidOpenResult {
  std::unique_ptr<HidConnection> connection;  // set when error is None
  HidOpenError error = HidOpenError::None;
  std::string message;                        // the system's words for the error
};

class HidTransport {
 public:
  virtual ~HidTransport() = default;
  virtual std::vector<HidDeviceInfo> enumerate() = 0;
  virtual HidOpenResult open(const std::string& path) = 0;
  // The node's HID report descriptor; empty where it cannot be read.
  virtual std::vector<uint8_t> reportDescriptor(const std::string& path) = 0;
};

// hidapi over hidraw, reading report descriptors from sysfs.
std::shared_ptr<HidTransport> makeHidapiTransport();

}  // namespace dentsim::devices
