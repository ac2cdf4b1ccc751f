// HID pedal report layouts: describe one, decode one report, and find the pedal's field in a report descriptor; pure functions, no I/O.
//
// Sections:
//   1. Report layouts: decode one report, describe a layout
//   2. Report descriptors: find the pedal's field
#include "devices/hid_pedal_descriptor.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace dentsim::devices {

// ============================================================================================
// 1. Report layouts
// ============================================================================================

std::string describeLayout(const PedalLayout& l) {
  std::string text;
  switch (l.input) {
    case PedalInput::Button: {
      char mask[8];
      std::snprintf(mask, sizeof mask, "%02x", l.button_mask);
      text = "switch: byte " + std::to_string(l.byte) + " mask 0x" + mask;
      break;
    }
    case PedalInput::Axis:
      text = "axis: byte " + std::to_string(l.byte) + " bit " + std::to_string(l.bit) + ", " + std::to_string(l.bits) +
             " bits, raw " + std::to_string(l.raw_min) + ".." + std::to_string(l.raw_max);
      break;
    case PedalInput::Key:
      text = l.key_code == 0 ? "keyboard switch: any key" : "keyboard switch: key " + std::to_string(l.key_code);
      break;
  }
  if (l.report_id >= 0) text += ", report " + std::to_string(l.report_id);
  if (l.invert) text += ", inverted";
  return text;
}

std::optional<double> decodePedalReport(const PedalLayout& l, std::span<const uint8_t> report) {
  if (l.report_id >= 0 && (report.empty() || report[0] != l.report_id)) return std::nullopt;
  double position = 0.0;
  switch (l.input) {
    case PedalInput::Button: {
      if (static_cast<size_t>(l.byte) >= report.size()) return std::nullopt;
      position = (report[l.byte] & l.button_mask) != 0 ? 1.0 : 0.0;
      break;
    }
    case PedalInput::Axis: {
      const size_t first_bit = static_cast<size_t>(l.byte) * 8 + static_cast<size_t>(l.bit);
      if (first_bit + static_cast<size_t>(l.bits) > report.size() * 8) return std::nullopt;
      // HID fields are little-endian bit strings: bit i of the field is bit (first_bit + i) of the report.
      uint64_t raw = 0;
      for (int i = 0; i < l.bits; ++i) {
        const size_t at = first_bit + static_cast<size_t>(i);
        raw |= static_cast<uint64_t>((report[at / 8] >> (at % 8)) & 1u) << i;
      }
      int64_t value = static_cast<int64_t>(raw);
      const bool is_signed = l.raw_min < 0 || l.raw_max < 0;
      if (is_signed && (raw >> (l.bits - 1)) & 1u) value -= int64_t{1} << l.bits;
      const double t = static_cast<double>(value - l.raw_min) / static_cast<double>(l.raw_max - l.raw_min);
      position = std::clamp(t, 0.0, 1.0);
      break;
    }
    case PedalInput::Key: {
      // Boot keyboard report: modifiers, a reserved byte, six key usages (after the report id, if any).
      const size_t base = l.report_id >= 0 ? 1 : 0;
      if (report.size() < base + 8) return std::nullopt;
      bool down = false;
      if (l.key_code == 0) down = report[base] != 0;
      for (size_t i = base + 2; i < base + 8; ++i) {
        // Usages 1..3 are the keyboard's error codes (rollover, POST fail, undefined), not keys.
        if (l.key_code == 0 ? report[i] >= 4 : report[i] == l.key_code) down = true;
      }
      position = down ? 1.0 : 0.0;
      break;
    }
  }
  if (l.invert) position = 1.0 - position;
  if (position < l.dead_band) position = 0.0;
  return position;
}

// ============================================================================================
// 2. Report descriptors (HID 1.11, section 6.2.2): walk the items, tracking each report's bit offset
// ============================================================================================

std::optional<PedalLayout> layoutFromReportDescriptor(std::span<const uint8_t> d) {
  struct Globals {
    uint32_t usage_page = 0;
    int64_t logical_min = 0;
    int64_t logical_max = 0;
    uint32_t report_size = 0;   // [bits]
    uint32_t report_count = 0;
    uint32_t report_id = 0;
  };
  Globals g;
  std::vector<Globals> stack;
  std::vector<uint32_t> usages;  // local: full usages (page << 16 | id)
  uint32_t usage_min = 0, usage_max = 0;
  bool have_range = false;
  bool numbered = false;
  std::array<uint32_t, 256> bit_offset{};  // per report id [bits]

  struct Found {
    int rank = 0;  // 3 accelerator/brake, 2 a Generic Desktop axis, 1 a button
    PedalLayout layout;
    uint32_t report_id = 0;
  };
  Found best;

  size_t i = 0;
  while (i < d.size()) {
    const uint8_t prefix = d[i];
    if (prefix == 0xFE) {  // long item: size, tag, data; no pedal uses them
      // Its size byte, its tag and its data must all be there, as for a short item.
      if (i + 2 >= d.size() || i + 3 + d[i + 1] > d.size()) return std::nullopt;
      i += 3 + d[i + 1];
      continue;
    }
    const size_t size = (prefix & 3u) == 3u ? 4 : (prefix & 3u);
    if (i + 1 + size > d.size()) return std::nullopt;
    uint32_t udata = 0;
    for (size_t k = 0; k < size; ++k) udata |= static_cast<uint32_t>(d[i + 1 + k]) << (8 * k);
    int64_t sdata = udata;
    if (size > 0 && (udata >> (8 * size - 1)) & 1u) sdata -= int64_t{1} << (8 * size);
    const uint8_t type = (prefix >> 2) & 3u;
    const uint8_t tag = prefix >> 4;
    i += 1 + size;

    if (type == 1) {  // global
      switch (tag) {
        case 0: g.usage_page = udata; break;
        case 1: g.logical_min = sdata; break;
        case 2: g.logical_max = sdata; break;
        case 7: g.report_size = udata; break;
        case 8: g.report_id = udata & 0xFFu; numbered = true; break;
        case 9: g.report_count = udata; break;
        case 10: stack.push_back(g); break;
        case 11:
          if (stack.empty()) return std::nullopt;
          g = stack.back();
          stack.pop_back();
          break;
        default: break;
      }
    } else if (type == 2) {  // local
      const uint32_t full = size == 4 ? udata : (g.usage_page << 16) | udata;
      if (tag == 0) usages.push_back(full);
      if (tag == 1) usage_min = full, have_range = true;
      if (tag == 2) usage_max = full, have_range = true;
    } else if (type == 0) {  // main
      if (tag == 8) {  // Input
        const bool constant = udata & 1u, variable = udata & 2u, relative = udata & 4u;
        uint32_t& offset = bit_offset[g.report_id];
        if (g.report_size > 32 || g.report_count > 4096) return std::nullopt;
        for (uint32_t f = 0; f < g.report_count; ++f) {
          uint32_t usage = 0;
          if (f < usages.size()) usage = usages[f];
          else if (have_range && usage_min + f <= usage_max) usage = usage_min + f;
          else if (!usages.empty()) usage = usages.back();
          const uint32_t page = usage >> 16, id = usage & 0xFFFFu;
          int rank = 0;
          if (!constant && variable && !relative) {
            if (page == 0x02 && (id == 0xC4 || id == 0xC5)) rank = 3;  // accelerator, brake
            else if (page == 0x01 && id >= 0x30 && id <= 0x36) rank = 2;  // X, Y, Z, Rx, Ry, Rz, Slider
            else if (page == 0x09 && g.report_size == 1) rank = 1;
          }
          const uint32_t at = offset + f * g.report_size;
          if (rank > best.rank) {
            // hidapi hands numbered reports over with the id as byte 0.
            const uint32_t at_in_buffer = at + (numbered ? 8u : 0u);
            if (at_in_buffer / 8 > static_cast<uint32_t>(kMaxPedalReportOffset)) continue;
            PedalLayout l;
            l.report_id = numbered ? static_cast<int>(g.report_id) : -1;
            l.byte = static_cast<int>(at_in_buffer / 8);
            l.bit = static_cast<int>(at_in_buffer % 8);
            if (rank == 1) {
              l.input = PedalInput::Button;
              l.button_mask = static_cast<uint8_t>(1u << l.bit);
              l.bit = 0;
            } else {
              if (g.report_size == 0) continue;
              l.input = PedalInput::Axis;
              l.bits = static_cast<int>(g.report_size);
              l.raw_min = g.logical_min;
              l.raw_max = g.logical_max;
              // A short item read as signed turns an intended 255 into -1; with a non-negative
              // minimum the maximum was meant unsigned.
              if (l.raw_min >= 0 && l.raw_max < l.raw_min) l.raw_max += int64_t{1} << l.bits;
              if (l.raw_max == l.raw_min) continue;
            }
            best = Found{rank, l, g.report_id};
          }
        }
        offset += g.report_size * g.report_count;
      }
      usages.clear();
      have_range = false;
      usage_min = usage_max = 0;
    }
  }
  if (best.rank == 0) return std::nullopt;
  return best.layout;
}

}  // namespace dentsim::devices
