// HID pedal report layouts: where a pedal's position sits in its input report, how to decode it, and how to find it in a report descriptor.
//
// Pure functions over bytes, no I/O, so the fuzzers and tests drive them directly; the pedal
// (hid_pedal.h) applies them to what its transport reads.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace dentsim::devices {

// A field may start anywhere within this many bytes of the report [bytes].
inline constexpr int kMaxPedalReportOffset = 255;

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

}  // namespace dentsim::devices
