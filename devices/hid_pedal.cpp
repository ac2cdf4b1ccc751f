// USB HID foot pedals: spec parsing, the known-pedal table, and the reader thread behind FootPedal.
//
// The report layouts and descriptor parser are in hid_pedal_descriptor.cpp (pure), the hidapi
// transport in hid_pedal_transport.cpp; this file joins them into a pedal.
//
// Sections:
//   1. Spec parsing
//   2. Known pedals and which HID interfaces count as pedals
//   3. HidPedal: the reader thread, unplug and replug
//   4. Entry points
#include "devices/hid_pedal.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstring>
#include <thread>

#include "core/permission_advice.h"
#include "io/parse_guard.h"

namespace dentsim::devices {
namespace {

// The largest input report read in one go; full-speed interrupt reports are at most 64 bytes [bytes].
constexpr size_t kMaxReportBytes = 256;

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
// 1. Spec parsing
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
      if (f.size() != 2 || !parseInt(f[0], &l.byte) || !parseInt(f[1], &bit) || l.byte < 0 || l.byte > kMaxPedalReportOffset ||
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
      if (l.byte < 0 || l.byte > kMaxPedalReportOffset || l.bit < 0 || l.bit > 7) {
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
// 2. Known pedals, and which HID interfaces count as pedals
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

}  // namespace

std::span<const KnownPedal> knownPedals() { return kKnownPedals; }

// ============================================================================================
// 3. HidPedal
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
// 4. Entry points
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
