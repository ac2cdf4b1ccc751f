// USB HID foot pedals: spec parsing, report decoding, the known-pedal table, the hidapi transport and the reader thread.
//
// Sections:
//   1. Report layouts: decode one report, describe a layout
//   2. Report descriptors: find the pedal's field
//   3. Spec parsing
//   4. Known pedals and which HID interfaces count as pedals
//   5. The hidapi transport
//   6. HidPedal: the reader thread, unplug and replug
//   7. Entry points
#include "devices/hid_pedal.h"

#include <hidapi.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>

#include "io/parse_guard.h"

namespace dentsim::devices {
namespace {

// The largest input report read in one go; full-speed interrupt reports are at most 64 bytes [bytes].
constexpr size_t kMaxReportBytes = 256;
// A field may start anywhere within this many bytes of the report.
constexpr int kMaxReportOffset = 255;

std::string hex4(uint16_t v) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", v);
  return text;
}

bool containsNoCase(const std::string& text, const char* word) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower.find(word) != std::string::npos;
}

}  // namespace

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
            if (at_in_buffer / 8 > static_cast<uint32_t>(kMaxReportOffset)) continue;
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

// ============================================================================================
// 3. Spec parsing
// ============================================================================================
namespace {

std::vector<std::string> splitOn(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

template <class Int>
bool parseInt(const std::string& text, Int* out, int base = 10) {
  if (text.empty()) return false;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (base == 0) {  // decimal, or hex with 0x
    base = 10;
    if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) first += 2, base = 16;
    if (base == 16 && (*first == '-' || *first == '+')) return false;  // "0x-5" is no number
  }
  const auto [ptr, ec] = std::from_chars(first, last, *out, base);
  return ec == std::errc() && ptr == last;
}

bool parseDouble(const std::string& text, double* out) {
  if (text.empty()) return false;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), *out);
  return ec == std::errc() && ptr == text.data() + text.size();
}

}  // namespace

Result<HidPedalSpec> parseHidPedalSpec(const std::string& spec_in) {
  std::string body = spec_in.rfind("hid:", 0) == 0 ? spec_in.substr(4) : spec_in;
  HidPedalSpec spec;
  spec.text = "hid:" + body;
  // The spec is the user's text: echoed escaped, so a stray line break cannot split the message.
  const auto fail = [&](const std::string& what) { return makeError(escapeControl(spec.text), escapeControl(what)); };

  const std::vector<std::string> parts = splitOn(body, ',');
  const std::string& target = parts[0];
  if (target.empty()) return fail("no pedal named (want hid:N, hid:VVVV:PPPP or hid:/dev/hidrawN)");

  if (target[0] == '/') {
    spec.target = HidPedalSpec::Target::Path;
    spec.path = target;
  } else if (std::all_of(target.begin(), target.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
    spec.target = HidPedalSpec::Target::Index;
    if (!parseInt(target, &spec.index) || spec.index > 999) return fail("pedal index '" + target + "' out of range [0, 999]");
  } else {
    spec.target = HidPedalSpec::Target::VendorProduct;
    const std::vector<std::string> ids = splitOn(target, ':');
    if (ids.size() != 2 || ids[0].size() != 4 || ids[1].size() != 4 || !parseInt(ids[0], &spec.vendor_id, 16) ||
        !parseInt(ids[1], &spec.product_id, 16)) {
      return fail("bad target '" + target + "' (want an index, VVVV:PPPP in hex like 0c45:7403, or /dev/hidrawN)");
    }
  }

  for (size_t p = 1; p < parts.size(); ++p) {
    const std::string& option = parts[p];
    const size_t eq = option.find('=');
    const std::string key = option.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : option.substr(eq + 1);
    const bool has_value = eq != std::string::npos;
    const auto needLayoutSlot = [&]() -> bool { return !spec.layout.has_value(); };

    if (key == "button") {
      if (!needLayoutSlot()) return fail("more than one of button=, axis=, key=");
      const std::vector<std::string> f = splitOn(value, ':');
      PedalLayout l;
      int bit = 0;
      if (f.size() != 2 || !parseInt(f[0], &l.byte) || !parseInt(f[1], &bit) || l.byte < 0 || l.byte > kMaxReportOffset ||
          bit < 0 || bit > 7) {
        return fail("bad button '" + value + "' (want BYTE:BIT, byte [0, 255], bit [0, 7], e.g. button=0:0)");
      }
      l.input = PedalInput::Button;
      l.button_mask = static_cast<uint8_t>(1u << bit);
      spec.layout = l;
    } else if (key == "axis") {
      if (!needLayoutSlot()) return fail("more than one of button=, axis=, key=");
      const std::vector<std::string> f = splitOn(value, ':');
      PedalLayout l;
      l.input = PedalInput::Axis;
      bool good = f.size() == 4;
      if (good) {
        const std::vector<std::string> at = splitOn(f[0], '.');
        good = at.size() <= 2 && parseInt(at[0], &l.byte) && (at.size() == 1 || parseInt(at[1], &l.bit)) &&
               parseInt(f[1], &l.bits) && parseInt(f[2], &l.raw_min, 0) && parseInt(f[3], &l.raw_max, 0);
      }
      if (!good) return fail("bad axis '" + value + "' (want BYTE[.BIT]:BITS:MIN:MAX, e.g. axis=1:8:0:255)");
      if (l.byte < 0 || l.byte > kMaxReportOffset || l.bit < 0 || l.bit > 7) {
        return fail("axis '" + value + "': byte must be in [0, 255] and bit in [0, 7]");
      }
      if (l.bits < 1 || l.bits > 32) return fail("axis '" + value + "': bits must be in [1, 32]");
      if (l.raw_min == l.raw_max) return fail("axis '" + value + "': MIN and MAX are equal");
      const bool is_signed = l.raw_min < 0 || l.raw_max < 0;
      const int64_t lo = is_signed ? -(int64_t{1} << (l.bits - 1)) : 0;
      const int64_t hi = is_signed ? (int64_t{1} << (l.bits - 1)) - 1 : (int64_t{1} << l.bits) - 1;
      if (std::min(l.raw_min, l.raw_max) < lo || std::max(l.raw_min, l.raw_max) > hi) {
        return fail("axis '" + value + "': MIN and MAX must fit " + std::to_string(l.bits) + " bits [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
      }
      spec.layout = l;
    } else if (key == "key") {
      if (!needLayoutSlot()) return fail("more than one of button=, axis=, key=");
      PedalLayout l;
      l.input = PedalInput::Key;
      int code = 0;
      if (has_value && (!parseInt(value, &code, 0) || code < 4 || code > 255)) {
        return fail("bad key '" + value + "' (want a HID keyboard usage [4, 255], e.g. key=0x05 for B)");
      }
      l.key_code = static_cast<uint8_t>(code);
      spec.layout = l;
    } else if (key == "invert" && !has_value) {
      spec.invert = true;
    } else if (key == "deadband") {
      double band = 0.0;
      if (!parseDouble(value, &band) || !(band >= 0.0 && band < 0.5)) {
        return fail("bad deadband '" + value + "' (want a fraction in [0, 0.5), e.g. deadband=0.03)");
      }
      spec.dead_band = band;
    } else if (key == "report") {
      int id = 0;
      if (!parseInt(value, &id, 0) || id < 0 || id > 255) return fail("bad report id '" + value + "' (want [0, 255])");
      spec.report_id = id;
    } else if (key == "serial") {
      if (value.empty()) return fail("empty serial");
      spec.serial = value;
    } else {
      return fail("unknown option '" + option +
                  "' (known: button=B:b, axis=B[.b]:N:MIN:MAX, key[=CODE], invert, deadband=F, report=ID, serial=S)");
    }
  }
  return spec;
}

// ============================================================================================
// 4. Known pedals, and which HID interfaces count as pedals
// ============================================================================================

namespace {

constexpr PedalLayout keyboardSwitch() {
  PedalLayout l;
  l.input = PedalInput::Key;
  return l;
}

constexpr PedalLayout bitsSwitch(int byte, uint8_t mask) {
  PedalLayout l;
  l.input = PedalInput::Button;
  l.byte = byte;
  l.button_mask = mask;
  return l;
}

// PCsensor/Scythe style foot switches enumerate as keyboards and type a programmable key (the IDs
// are those the open-source `footswitch` programming tool lists). The VEC Infinity IN-USB-2
// transcription pedal sends two bytes, the left, middle and right pedals as bits 0, 1, 2 of the
// first; any of them runs the turbine.
constexpr KnownPedal kKnownPedals[] = {
    {0x0c45, 0x7403, "PCsensor FootSwitch", 0x01, 0x06, keyboardSwitch()},
    {0x0c45, 0x7404, "PCsensor FootSwitch (3 pedals)", 0x01, 0x06, keyboardSwitch()},
    {0x413d, 0x2107, "PCsensor FootSwitch", 0x01, 0x06, keyboardSwitch()},
    {0x1a86, 0xe026, "iKKEGOL foot switch", 0x01, 0x06, keyboardSwitch()},
    {0x05f3, 0x00ff, "VEC Infinity IN-USB-2", 0, 0, bitsSwitch(0, 0x07)},
};

const KnownPedal* findKnown(uint16_t vendor_id, uint16_t product_id) {
  for (const KnownPedal& k : kKnownPedals) {
    if (k.vendor_id == vendor_id && k.product_id == product_id) return &k;
  }
  return nullptr;
}

std::string modelOf(const HidDeviceInfo& info, const KnownPedal* known) {
  if (known != nullptr) return known->model;
  std::string model = info.manufacturer;
  if (!info.product.empty()) model += (model.empty() ? "" : " ") + info.product;
  return model.empty() ? "USB foot pedal" : model;
}

const char* kindWord(const std::optional<PedalLayout>& l) {
  if (!l) return "layout unknown";
  return l->input == PedalInput::Axis ? "proportional" : "switch";
}

struct Candidate {
  HidDeviceInfo info;
  std::optional<PedalLayout> layout;  // nullopt: the user must state it
  std::string model;
};

// The layout a device's own interface suggests, from the table, its descriptor, or its usage.
std::optional<PedalLayout> layoutOf(HidTransport& transport, const HidDeviceInfo& info) {
  if (const KnownPedal* known = findKnown(info.vendor_id, info.product_id)) return known->layout;
  if (auto from_descriptor = layoutFromReportDescriptor(transport.reportDescriptor(info.path))) return from_descriptor;
  if (info.usage_page == 0x01 && info.usage == 0x06) return keyboardSwitch();  // a keyboard sold as a foot switch
  return std::nullopt;
}

std::vector<Candidate> pedalCandidates(HidTransport& transport) {
  std::vector<Candidate> found;
  for (const HidDeviceInfo& info : transport.enumerate()) {
    const KnownPedal* known = findKnown(info.vendor_id, info.product_id);
    if (known != nullptr) {
      if (known->usage_page != 0 && (info.usage_page != known->usage_page || info.usage != known->usage)) continue;
      found.push_back({info, known->layout, modelOf(info, known)});
      continue;
    }
    // Unknown devices count when they say what they are: a name with pedal or foot in it, or a
    // Simulation Controls collection (racing pedals). Plain keyboards and joysticks do not.
    const std::string words = info.manufacturer + " " + info.product;
    const bool named = containsNoCase(words, "pedal") || containsNoCase(words, "foot");
    if (!named && info.usage_page != 0x02) continue;
    found.push_back({info, layoutOf(transport, info), modelOf(info, nullptr)});
  }
  return found;
}

std::string locationOf(const HidDeviceInfo& info) {
  return info.path + " (" + hex4(info.vendor_id) + ":" + hex4(info.product_id) + ")";
}

std::string permissionAdvice(const std::string& path) {
  return "permission denied on " + path +
         ": install devices/70-dentsim.rules into /etc/udev/rules.d (see the file), then replug the pedal";
}

}  // namespace

std::span<const KnownPedal> knownPedals() { return kKnownPedals; }

// ============================================================================================
// 5. The hidapi transport
// ============================================================================================
namespace {

// hidapi speaks wchar_t (UTF-32 on Linux); the rest of dentsim speaks UTF-8.
std::string toUtf8(const wchar_t* text) {
  std::string out;
  if (text == nullptr) return out;
  for (; *text != 0; ++text) {
    const auto c = static_cast<uint32_t>(*text);
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x110000) {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

class HidapiConnection final : public HidConnection {
 public:
  explicit HidapiConnection(hid_device* device) : device_(device) {}
  ~HidapiConnection() override { hid_close(device_); }
  HidapiConnection(const HidapiConnection&) = delete;
  HidapiConnection& operator=(const HidapiConnection&) = delete;

  int read(uint8_t* buffer, size_t capacity, int timeout_ms) override {
    return hid_read_timeout(device_, buffer, capacity, timeout_ms);
  }
  std::string error() const override {
    const std::string text = toUtf8(hid_error(device_));
    return text.empty() ? "read failed" : text;
  }

 private:
  hid_device* device_;
};

class HidapiTransport final : public HidTransport {
 public:
  HidapiTransport() { hid_init(); }

  std::vector<HidDeviceInfo> enumerate() override {
    std::vector<HidDeviceInfo> list;
    hid_device_info* all = hid_enumerate(0, 0);
    for (const hid_device_info* d = all; d != nullptr; d = d->next) {
      HidDeviceInfo info;
      info.path = d->path != nullptr ? d->path : "";
      info.vendor_id = d->vendor_id;
      info.product_id = d->product_id;
      info.serial = toUtf8(d->serial_number);
      info.manufacturer = toUtf8(d->manufacturer_string);
      info.product = toUtf8(d->product_string);
      info.usage_page = d->usage_page;
      info.usage = d->usage;
      info.interface_number = d->interface_number;
      info.permitted = ::access(info.path.c_str(), R_OK | W_OK) == 0;
      list.push_back(std::move(info));
    }
    hid_free_enumeration(all);
    return list;
  }

  HidOpenResult open(const std::string& path) override {
    HidOpenResult result;
    // Ask the file system first: hidapi's own message does not say which way the open failed.
    if (::access(path.c_str(), F_OK) != 0) {
      result.error = HidOpenError::NotFound;
      result.message = path + ": " + std::strerror(errno);
      return result;
    }
    if (::access(path.c_str(), R_OK | W_OK) != 0 && errno == EACCES) {
      result.error = HidOpenError::PermissionDenied;
      result.message = path + ": " + std::strerror(EACCES);
      return result;
    }
    hid_device* device = hid_open_path(path.c_str());
    if (device == nullptr) {
      const int saved = errno;
      result.error = saved == EACCES ? HidOpenError::PermissionDenied
                     : saved == ENOENT || saved == ENODEV ? HidOpenError::NotFound
                                                          : HidOpenError::Failed;
      result.message = toUtf8(hid_error(nullptr));
      if (result.message.empty()) result.message = path + ": " + std::strerror(saved);
      return result;
    }
    result.connection = std::make_unique<HidapiConnection>(device);
    return result;
  }

  std::vector<uint8_t> reportDescriptor(const std::string& path) override {
    // hidapi 0.13 has no call for it; the kernel exposes it beside the hidraw node.
    const size_t slash = path.rfind('/');
    const std::string node = slash == std::string::npos ? path : path.substr(slash + 1);
    if (node.rfind("hidraw", 0) != 0) return {};
    std::ifstream file("/sys/class/hidraw/" + node + "/device/report_descriptor", std::ios::binary);
    if (!file) return {};
    constexpr size_t kMaxDescriptorBytes = 4096;  // the kernel's HID_MAX_DESCRIPTOR_SIZE
    std::vector<uint8_t> bytes(kMaxDescriptorBytes);
    file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<size_t>(file.gcount()));
    return bytes;
  }
};

}  // namespace

std::shared_ptr<HidTransport> makeHidapiTransport() { return std::make_shared<HidapiTransport>(); }

// ============================================================================================
// 6. HidPedal
// ============================================================================================
namespace {

// What identifies the pedal across a replug, when the hidraw node number may change.
struct Identity {
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string serial;
  int interface_number = -1;
  uint16_t usage_page = 0;
  uint16_t usage = 0;
  std::string path;

  bool matches(const HidDeviceInfo& info) const {
    return info.vendor_id == vendor_id && info.product_id == product_id && info.serial == serial &&
           info.interface_number == interface_number && info.usage_page == usage_page && info.usage == usage;
  }
};

class HidPedal final : public FootPedal {
 public:
  HidPedal(HidPedalSpec spec, std::shared_ptr<HidTransport> transport, const HidPedalOptions& options)
      : spec_(std::move(spec)), transport_(std::move(transport)), options_(options) {
    setState(DeviceState::Disconnected, "not opened");
  }
  ~HidPedal() override { close(); }

  std::string name() const override { return spec_.text; }

  Status open() override {
    if (reader_.joinable() && !reader_done_.load(std::memory_order_acquire)) return Ok{};
    stopReader();
    wanted_ = true;
    next_attempt_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.reconnect_interval_ms);
    return connect();
  }

  void close() override {
    wanted_ = false;
    stopReader();
    value_.store(0.0, std::memory_order_release);
    if (state() != DeviceState::Disconnected || reason() != "closed") setState(DeviceState::Disconnected, "closed");
  }

  void service() override {
    if (!wanted_) return;
    if (reader_.joinable() && !reader_done_.load(std::memory_order_acquire)) return;
    stopReader();  // the reader ended on a read error; its reason stays until a reconnect succeeds
    const auto now = std::chrono::steady_clock::now();
    if (now < next_attempt_) return;
    next_attempt_ = now + std::chrono::milliseconds(options_.reconnect_interval_ms);
    (void)connect();
  }

  double value() const override {
    if (state() != DeviceState::Ready) return 0.0;
    return value_.load(std::memory_order_acquire);
  }

 private:
  struct Located {
    HidDeviceInfo info;
    PedalLayout layout;
  };

  // The device the spec (or, after the first open, the identity) names, and its layout.
  Result<Located> locate() {
    std::vector<HidDeviceInfo> all = transport_->enumerate();
    const HidDeviceInfo* chosen = nullptr;
    std::optional<PedalLayout> suggested;
    if (identity_) {
      for (const HidDeviceInfo& info : all) {
        if (identity_->matches(info)) { chosen = &info; break; }
      }
      if (chosen == nullptr) {
        for (const HidDeviceInfo& info : all) {
          if (info.path == identity_->path) { chosen = &info; break; }
        }
      }
      if (chosen == nullptr) return makeError(spec_.text, "not plugged in (was " + identity_->path + ")");
      return Located{*chosen, layout_};
    }

    switch (spec_.target) {
      case HidPedalSpec::Target::Index: {
        std::vector<Candidate> pedals = pedalCandidates(*transport_);
        if (!spec_.serial.empty()) {
          std::erase_if(pedals, [&](const Candidate& c) { return c.info.serial != spec_.serial; });
        }
        if (static_cast<size_t>(spec_.index) >= pedals.size()) {
          return makeError(spec_.text, "no such pedal: " + std::to_string(pedals.size()) +
                                           " found (`dentsim devices` lists them)");
        }
        const Candidate& c = pedals[static_cast<size_t>(spec_.index)];
        for (const HidDeviceInfo& info : all) {
          if (info.path == c.info.path) chosen = &info;
        }
        if (chosen == nullptr) return makeError(spec_.text, "no such pedal: it went away while being opened");
        suggested = c.layout;
        break;
      }
      case HidPedalSpec::Target::VendorProduct: {
        const KnownPedal* known = findKnown(spec_.vendor_id, spec_.product_id);
        const bool wants_keyboard = spec_.layout ? spec_.layout->input == PedalInput::Key
                                                 : known != nullptr && known->usage_page == 0x01 && known->usage == 0x06;
        for (const HidDeviceInfo& info : all) {
          if (info.vendor_id != spec_.vendor_id || info.product_id != spec_.product_id) continue;
          if (!spec_.serial.empty() && info.serial != spec_.serial) continue;
          const bool keyboard = info.usage_page == 0x01 && info.usage == 0x06;
          // Multi-interface devices: take the interface that carries the pedal, else the first.
          if (chosen == nullptr || (wants_keyboard && keyboard && !(chosen->usage_page == 0x01 && chosen->usage == 0x06))) {
            chosen = &info;
          }
        }
        if (chosen == nullptr) return makeError(spec_.text, "not found: no HID device " + hex4(spec_.vendor_id) + ":" +
                                                                hex4(spec_.product_id) + " is plugged in");
        break;
      }
      case HidPedalSpec::Target::Path: {
        for (const HidDeviceInfo& info : all) {
          if (info.path == spec_.path) chosen = &info;
        }
        if (chosen == nullptr) return makeError(spec_.text, "not found: " + spec_.path + " is no HID device");
        break;
      }
    }

    std::optional<PedalLayout> layout = spec_.layout;
    if (!layout) layout = suggested ? suggested : layoutOf(*transport_, *chosen);
    if (!layout) {
      return makeError(spec_.text, "cannot tell the report layout of " + locationOf(*chosen) +
                                       ": state it, e.g. " + spec_.text + ",button=0:0 or " + spec_.text +
                                       ",axis=1:8:0:255");
    }
    if (spec_.invert) layout->invert = *spec_.invert;
    if (spec_.dead_band) layout->dead_band = *spec_.dead_band;
    if (spec_.report_id) layout->report_id = *spec_.report_id;
    return Located{*chosen, *layout};
  }

  Status connect() {
    Result<Located> found = locate();
    if (!found) {
      setState(DeviceState::Disconnected, found.message());
      return found.error();
    }
    const HidDeviceInfo& info = found->info;
    HidOpenResult opened = transport_->open(info.path);
    if (opened.error != HidOpenError::None || !opened.connection) {
      const std::string where = spec_.text + " (" + locationOf(info) + ")";
      std::string why;
      switch (opened.error) {
        case HidOpenError::PermissionDenied: why = permissionAdvice(info.path); break;
        case HidOpenError::NotFound: why = "not plugged in (" + opened.message + ")"; break;
        default: why = "cannot open: " + opened.message; break;
      }
      setState(DeviceState::Disconnected, where + ": " + why);
      return makeError(where, why);
    }
    layout_ = found->layout;
    identity_ = Identity{info.vendor_id, info.product_id, info.serial, info.interface_number,
                         info.usage_page, info.usage, info.path};
    location_ = locationOf(info);
    connection_ = std::move(opened.connection);
    value_.store(0.0, std::memory_order_release);
    stop_.store(false, std::memory_order_release);
    reader_done_.store(false, std::memory_order_release);
    // Ready before the reader starts, so a read error at once is not overwritten.
    setState(DeviceState::Ready);
    reader_ = std::thread([this] { readLoop(); });
    return Ok{};
  }

  // Reader thread: one report at a time into value_, until stopped or the device fails.
  void readLoop() {
    std::array<uint8_t, kMaxReportBytes> report{};
    while (!stop_.load(std::memory_order_acquire)) {
      const int n = connection_->read(report.data(), report.size(), options_.read_timeout_ms);
      if (n < 0) {
        // The turbine stops before anyone reads the new state.
        value_.store(0.0, std::memory_order_release);
        setState(DeviceState::Disconnected,
                 spec_.text + " (" + location_ + "): unplugged or failed (" + connection_->error() + "); plug it in again");
        reader_done_.store(true, std::memory_order_release);
        return;
      }
      if (n == 0) continue;
      const size_t size = std::min(static_cast<size_t>(n), report.size());
      if (const std::optional<double> position = decodePedalReport(layout_, std::span(report.data(), size))) {
        value_.store(*position, std::memory_order_release);
      }
    }
    reader_done_.store(true, std::memory_order_release);
  }

  // Control thread: end the reader (within one read timeout) and close the device.
  void stopReader() {
    stop_.store(true, std::memory_order_release);
    if (reader_.joinable()) reader_.join();
    connection_.reset();
  }

  const HidPedalSpec spec_;
  const std::shared_ptr<HidTransport> transport_;
  const HidPedalOptions options_;

  // Control thread; the reader reads layout_, location_ and connection_ only while it runs.
  bool wanted_ = false;  // open() was called and close() not since: service() reconnects
  std::optional<Identity> identity_;
  PedalLayout layout_;
  std::string location_;
  std::unique_ptr<HidConnection> connection_;
  std::thread reader_;
  std::chrono::steady_clock::time_point next_attempt_{};

  // Between the threads.
  std::atomic<bool> stop_{false};
  std::atomic<bool> reader_done_{false};
  std::atomic<double> value_{0.0};  // the latest position [0, 1]
};

}  // namespace

// ============================================================================================
// 7. Entry points
// ============================================================================================

std::vector<DeviceEntry> enumerateHidPedals(HidTransport& transport) {
  std::vector<DeviceEntry> entries;
  const std::vector<Candidate> pedals = pedalCandidates(transport);
  for (size_t i = 0; i < pedals.size(); ++i) {
    const Candidate& c = pedals[i];
    DeviceEntry e;
    e.name = "hid:" + std::to_string(i);
    e.kind = "pedal";
    e.model = c.model + " (" + kindWord(c.layout) + ")";
    e.location = locationOf(c.info);
    if (!c.info.permitted) {
      e.state = DeviceState::Disconnected;
      e.reason = permissionAdvice(c.info.path);
    } else if (!c.layout) {
      e.state = DeviceState::Disconnected;
      e.reason = "cannot tell its report layout: state it, e.g. " + e.name + ",button=0:0 or " + e.name + ",axis=1:8:0:255";
    } else {
      e.state = DeviceState::Ready;
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

std::vector<DeviceEntry> enumerateHidPedals() {
  const std::shared_ptr<HidTransport> transport = makeHidapiTransport();
  return enumerateHidPedals(*transport);
}

Result<std::unique_ptr<FootPedal>> makeHidPedal(const std::string& spec, std::shared_ptr<HidTransport> transport,
                                                const HidPedalOptions& options) {
  Result<HidPedalSpec> parsed = parseHidPedalSpec(spec);
  if (!parsed) return parsed.error();
  std::unique_ptr<FootPedal> pedal = std::make_unique<HidPedal>(std::move(parsed).value(), std::move(transport), options);
  return pedal;
}

Result<std::unique_ptr<FootPedal>> makeHidPedal(const std::string& spec) {
  return makeHidPedal(spec, makeHidapiTransport());
}

}  // namespace dentsim::devices
