// Bounded, deterministic mutation fuzzing of the device parsers: pedal specs, pen names, HID report descriptors and the Falcon byte stream.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "devices/device_registry.h"
#include "devices/falcon_protocol.h"
#include "devices/hid_pedal.h"

#include "fuzz_mutations.h"

namespace dentsim::devices {
namespace {

using test::pick;

// Control bytes in the input are the one place where a parser may not quote it verbatim: it has
// to escape them (and may quote it) to stay on one line. Elsewhere the message must begin with the
// input as given.
bool printable(const std::string& text) {
  return std::none_of(text.begin(), text.end(), [](char c) { return uint8_t(c) < 0x20 || uint8_t(c) == 0x7f; });
}

void assertOneLine(const std::string& message, const std::string& input, int iteration) {
  const std::string context = "iteration " + std::to_string(iteration) + ", input " + ::testing::PrintToString(input) +
                              ": " + ::testing::PrintToString(message);
  ASSERT_FALSE(message.empty()) << context;
  ASSERT_EQ(message.find('\n'), std::string::npos) << context;
  ASSERT_EQ(message.find('\r'), std::string::npos) << context;
}

// Text cut at the separators of a spec or a pen name (",:=."), so that an edit swaps one field.
std::vector<std::string> splitFields(const std::string& text) {
  std::vector<std::string> pieces;
  std::string run;
  for (char c : text) {
    if (c == ',' || c == ':' || c == '=' || c == '.') {
      pieces.push_back(run);
      pieces.emplace_back(1, c);
      run.clear();
    } else {
      run += c;
    }
  }
  pieces.push_back(run);
  return pieces;
}

std::string join(const std::vector<std::string>& pieces) {
  std::string out;
  for (const std::string& p : pieces) out += p;
  return out;
}

// One field-level change: a field replaced by a tricky value, a field dropped or repeated, or a
// whole option or prefix inserted.
void mutateFields(std::vector<std::string>& pieces, const std::vector<std::string>& tricky,
                  const std::vector<std::string>& inserts, std::mt19937& rng) {
  const size_t i = pick(rng, pieces.size());
  switch (rng() % 4) {
    case 0: pieces[i] = tricky[pick(rng, tricky.size())]; break;
    case 1:
      if (pieces.size() > 1) pieces.erase(pieces.begin() + std::ptrdiff_t(i));
      break;
    case 2: pieces.insert(pieces.begin() + std::ptrdiff_t(i), pieces[pick(rng, pieces.size())]); break;
    default:
      pieces.insert(pieces.begin() + std::ptrdiff_t(pick(rng, pieces.size() + 1)), inserts[pick(rng, inserts.size())]);
      break;
  }
}

// 1 to 3 field edits, then one byte-level edit in half the cases.
std::string mutateText(const std::string& seed, const std::vector<std::string>& tricky,
                       const std::vector<std::string>& inserts, std::mt19937& rng) {
  std::vector<std::string> pieces = splitFields(seed);
  const int edits = 1 + int(rng() % 3);
  for (int e = 0; e < edits; ++e) mutateFields(pieces, tricky, inserts, rng);
  std::string text = join(pieces);
  if (rng() % 2) {
    std::vector<uint8_t> bytes(text.begin(), text.end());
    test::mutateBytesGeneric(bytes, rng);
    text.assign(bytes.begin(), bytes.end());
  }
  return text;
}

const std::vector<std::string> kTrickyFields = {
    "", "0", "-0", "+0", "1", "-1", "7", "8", "31", "32", "33", "63", "64", "255", "256", "-128", "999", "1000",
    "4294967295", "4294967296", "-2147483648", "2147483647", "9223372036854775807", "-9223372036854775808",
    "18446744073709551616", std::string(60, '9'), "0x", "0x10", "0xFF", "0x-5", "0x7fffffff", "0xffffffff",
    "0.5", "0.49999", "1e-300", "nan", "inf", "-inf", "0c45", "7403", "zzzz", "0C45", "hid", "/dev/hidraw0", "/",
    "button", "axis", "key", "invert", "deadband", "report", "serial", "virtual", "script", "replay", "falcon",
    "openhaptics", "Default", " ", "\t", "\n", "\r", std::string("\0", 1), "\xc2\xb5", "\xff", "\"", "'"};

// ---- HID pedal specs ----------------------------------------------------------------------------

const std::vector<std::string> kSpecSeeds = {
    "hid:0",
    "3",
    "hid:0c45:7403",
    "/dev/hidraw3",
    "hid:0,button=0:0",
    "hid:1,axis=1.4:10:0:1023,deadband=0.05,report=2",
    "0c45:7403,key=0x05,invert,serial=ABC123",
    "hid:05f3:00ff,axis=2:16:-32768:32767,invert",
    "hid:/dev/hidraw0,key,report=0x01,deadband=0",
    "413D:2107,button=255:7,serial=x",
    "7,axis=0:32:0x0:4294967295",
};

const std::vector<std::string> kSpecInserts = {
    ",button=0:0", ",axis=1:8:0:255", ",axis=0.7:1:0:1", ",key", ",key=255", ",invert", ",deadband=0.49",
    ",report=255", ",serial=S", ",", "hid:", ",,", ",invert=1", ":", "=", "."};

// Where no report id is given, every report counts; where one is, only reports that begin with it.
bool reportIsForPedal(const PedalLayout& l, std::span<const uint8_t> report) {
  return l.report_id < 0 || (!report.empty() && report[0] == l.report_id);
}

// The bytes a report needs to hold the pedal's field, from the layout's documented meaning.
size_t bytesNeeded(const PedalLayout& l) {
  switch (l.input) {
    case PedalInput::Button: return size_t(l.byte) + 1;
    case PedalInput::Axis: return (size_t(l.byte) * 8 + size_t(l.bit) + size_t(l.bits) + 7) / 8;
    case PedalInput::Key: return l.report_id >= 0 ? 9 : 8;
  }
  return 0;
}

// Reports of lengths around what the layout needs, zero, all ones and random, with the layout's
// report id in byte 0 and (once) the wrong id: each decodes to nullopt exactly when the report is not
// for the pedal or too short, and otherwise to a position in [0, 1]. Buffers are exactly the
// report's size, so the sanitizers catch a read past the end.
void checkDecodes(const PedalLayout& l, std::mt19937& rng, int iteration) {
  const size_t need = bytesNeeded(l);
  std::vector<size_t> sizes = {0, 1, need, need + 1, need + 7, 1 + pick(rng, need + 8)};
  if (need > 0) sizes.push_back(need - 1);
  for (size_t size : sizes) {
    for (int fill = 0; fill < 4; ++fill) {
      std::vector<uint8_t> report(size);
      for (uint8_t& b : report) b = fill == 0 ? 0x00 : fill == 1 ? 0xFF : uint8_t(rng());
      if (!report.empty() && l.report_id >= 0) report[0] = uint8_t(fill == 3 ? l.report_id + 1 : l.report_id);
      const std::optional<double> v = decodePedalReport(l, report);
      const bool expect_value = reportIsForPedal(l, report) && size >= need;
      ASSERT_EQ(v.has_value(), expect_value) << "iteration " << iteration << ": " << describeLayout(l) << ", report of " << size << " bytes";
      if (!v) continue;
      ASSERT_TRUE(std::isfinite(*v) && *v >= 0.0 && *v <= 1.0) << "iteration " << iteration << ": " << *v << " from " << describeLayout(l);
      if (l.input == PedalInput::Button) {
        // A switch is exactly pressed or not (any of its bits set), which a dead band below 1 keeps.
        const bool pressed = (report[size_t(l.byte)] & l.button_mask) != 0;
        ASSERT_EQ(*v, pressed != l.invert ? 1.0 : 0.0) << "iteration " << iteration;
      }
    }
  }
}

void checkSpec(const std::string& input, std::mt19937& rng, int iteration, int* accepted, int* rejected) {
  const Result<HidPedalSpec> r = parseHidPedalSpec(input);
  const std::string body = input.rfind("hid:", 0) == 0 ? input.substr(4) : input;
  const std::string name = "hid:" + body;
  if (!r.ok()) {
    ++*rejected;
    assertOneLine(r.message(), input, iteration);
    if (printable(input)) {
      ASSERT_EQ(r.message().rfind(name + ": ", 0), 0u) << r.message();
      ASSERT_GT(r.message().size(), name.size() + 2) << r.message();
    } else {
      ASSERT_NE(r.message().find("hid:"), std::string::npos) << ::testing::PrintToString(r.message());
    }
    return;
  }
  ++*accepted;
  const HidPedalSpec& s = *r;
  ASSERT_EQ(s.text, name);
  const std::string target = body.substr(0, body.find(','));
  switch (s.target) {
    case HidPedalSpec::Target::Index:
      ASSERT_TRUE(!target.empty() && std::all_of(target.begin(), target.end(), [](char c) { return c >= '0' && c <= '9'; })) << input;
      ASSERT_EQ(s.index, std::stoi(target)) << input;
      ASSERT_TRUE(s.index >= 0 && s.index <= 999) << input;
      break;
    case HidPedalSpec::Target::VendorProduct: {
      char ids[16];
      std::snprintf(ids, sizeof ids, "%04x:%04x", unsigned(s.vendor_id), unsigned(s.product_id));
      std::string lower = target;
      for (char& c : lower) c = (c >= 'A' && c <= 'F') ? char(c - 'A' + 'a') : c;
      ASSERT_EQ(lower, ids) << input;
      break;
    }
    case HidPedalSpec::Target::Path:
      ASSERT_EQ(s.path, target) << input;
      ASSERT_EQ(s.path[0], '/') << input;
      break;
  }
  if (s.dead_band) {
    ASSERT_TRUE(*s.dead_band >= 0.0 && *s.dead_band < 0.5) << input;
  }
  if (s.report_id) {
    ASSERT_TRUE(*s.report_id >= 0 && *s.report_id <= 255) << input;
  }
  if (!s.layout) return;
  PedalLayout l = *s.layout;
  switch (l.input) {
    case PedalInput::Button:
      ASSERT_TRUE(l.byte >= 0 && l.byte <= 255) << input;
      ASSERT_EQ(std::popcount(l.button_mask), 1) << input;
      break;
    case PedalInput::Axis: {
      ASSERT_TRUE(l.byte >= 0 && l.byte <= 255 && l.bit >= 0 && l.bit <= 7) << input;
      ASSERT_TRUE(l.bits >= 1 && l.bits <= 32) << input;
      ASSERT_NE(l.raw_min, l.raw_max) << input;
      const bool is_signed = l.raw_min < 0 || l.raw_max < 0;
      const int64_t lo = is_signed ? -(int64_t{1} << (l.bits - 1)) : 0;
      const int64_t hi = is_signed ? (int64_t{1} << (l.bits - 1)) - 1 : (int64_t{1} << l.bits) - 1;
      ASSERT_TRUE(std::min(l.raw_min, l.raw_max) >= lo && std::max(l.raw_min, l.raw_max) <= hi) << input;
      break;
    }
    case PedalInput::Key:
      ASSERT_TRUE(l.key_code == 0 || l.key_code >= 4) << input;
      break;
  }
  // The options adjust the layout the way the pedal applies them.
  if (s.invert) l.invert = *s.invert;
  if (s.dead_band) l.dead_band = *s.dead_band;
  if (s.report_id) l.report_id = *s.report_id;
  checkDecodes(l, rng, iteration);
}

TEST(DeviceParsersFuzz, SeedSpecsAreAccepted) {
  std::mt19937 rng(1);
  int accepted = 0, rejected = 0;
  for (size_t i = 0; i < kSpecSeeds.size(); ++i) {
    checkSpec(kSpecSeeds[i], rng, int(i), &accepted, &rejected);
    if (HasFatalFailure()) return;
  }
  EXPECT_EQ(accepted, int(kSpecSeeds.size()));
}

// The smallest cases of what the mutations find first: a line break typed into a name.
TEST(DeviceParsersFuzz, LineBreaksInANameStayOnOneLine) {
  for (const std::string spec : {"0\n", "hid:0,frob\r\nnicate", "0c45:74\n3"}) {
    const Result<HidPedalSpec> r = parseHidPedalSpec(spec);
    ASSERT_FALSE(r.ok()) << ::testing::PrintToString(spec);
    assertOneLine(r.message(), spec, 0);
  }
  for (const std::string pen : {"falcon:\n", "mouse\r\nvirtual"}) {
    const Result<PenName> r = parsePenName(pen);
    ASSERT_FALSE(r.ok()) << ::testing::PrintToString(pen);
    assertOneLine(r.message(), pen, 0);
  }
}

TEST(DeviceParsersFuzz, MutatedPedalSpecs) {
  std::mt19937 rng(20250817u);
  int accepted = 0, rejected = 0, with_layout = 0;
  for (int it = 0; it < 20000; ++it) {
    const std::string text = mutateText(kSpecSeeds[pick(rng, kSpecSeeds.size())], kTrickyFields, kSpecInserts, rng);
    const int before = accepted;
    checkSpec(text, rng, it, &accepted, &rejected);
    if (HasFatalFailure()) return;
    if (accepted > before && parseHidPedalSpec(text)->layout) ++with_layout;
  }
  // Both outcomes, and layouts to decode with, or the mutations are not exercising the parser.
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(rejected, 1000);
  EXPECT_GT(with_layout, 300);
}

// ---- pen names ----------------------------------------------------------------------------------

const std::vector<std::string> kPenSeeds = {
    "virtual", "falcon", "falcon:0", "falcon:63", "script:paths/a.csv", "replay:s.dses", "openhaptics",
    "openhaptics:Left Touch", "script:a:b.csv"};

const std::vector<std::string> kPenInserts = {":", "virtual", "falcon:", "script:", ":1", "openhaptics:", "replay:x"};

bool allDigits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

void checkPenName(const std::string& input, int iteration, int* accepted, int* rejected) {
  const Result<PenName> r = parsePenName(input);
  if (!r.ok()) {
    ++*rejected;
    assertOneLine(r.message(), input, iteration);
    if (printable(input)) {
      const std::string name = "pen '" + input + "'";
      ASSERT_EQ(r.message().rfind(name + ": ", 0), 0u) << r.message();
      ASSERT_GT(r.message().size(), name.size() + 2) << r.message();
    } else {
      ASSERT_NE(r.message().find("pen "), std::string::npos) << ::testing::PrintToString(r.message());
    }
    return;
  }
  ++*accepted;
  const PenName& n = *r;
  const size_t colon = input.find(':');
  const std::string after = colon == std::string::npos ? std::string() : input.substr(colon + 1);
  ASSERT_EQ(n.text, input);
  ASSERT_EQ(n.backend, input.substr(0, colon));
  if (n.backend == "virtual") {
    ASSERT_EQ(colon, std::string::npos) << input;
    ASSERT_TRUE(n.software());
  } else if (n.backend == "script" || n.backend == "replay") {
    ASSERT_FALSE(after.empty()) << input;
    ASSERT_EQ(n.arg, after);
    ASSERT_TRUE(n.software());
  } else if (n.backend == "falcon") {
    ASSERT_EQ(n.arg, after.empty() ? "0" : after);
    // A bus index 0..63 in decimal ("-0" is zero too).
    const std::string digits = n.arg[0] == '-' ? n.arg.substr(1) : n.arg;
    ASSERT_TRUE(allDigits(digits)) << input;
    const size_t first = std::min(digits.find_first_not_of('0'), digits.size());
    ASSERT_LE(digits.size() - first, 2u) << input;
    const int index = first == digits.size() ? 0 : std::stoi(digits.substr(first));
    ASSERT_TRUE(index >= 0 && index <= 63 && (n.arg[0] != '-' || index == 0)) << input;
    ASSERT_FALSE(n.software());
  } else {
    ASSERT_EQ(n.backend, "openhaptics") << input;
    ASSERT_EQ(n.arg, after.empty() ? "Default" : after);
    ASSERT_FALSE(n.software());
  }
}

TEST(DeviceParsersFuzz, MutatedPenNames) {
  std::mt19937 rng(777u);
  int accepted = 0, rejected = 0;
  for (size_t i = 0; i < kPenSeeds.size(); ++i) {
    checkPenName(kPenSeeds[i], int(i), &accepted, &rejected);
    if (HasFatalFailure()) return;
  }
  ASSERT_EQ(accepted, int(kPenSeeds.size()));
  for (int it = 0; it < 20000; ++it) {
    checkPenName(mutateText(kPenSeeds[pick(rng, kPenSeeds.size())], kTrickyFields, kPenInserts, rng), it, &accepted, &rejected);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(rejected, 1000);
}

// ---- HID report descriptors ---------------------------------------------------------------------

// A proportional pedal in numbered report 2: 4 constant bits, then X as 10 bits, 0..1023, then 2
// bits of padding. hidapi puts the id in byte 0, so X starts at bit 8 + 4 = 12: byte 1, bit 4.
const std::vector<uint8_t> kAxisDescriptor = {
    0x05, 0x01,        // Usage Page (Generic Desktop)
    0x09, 0x04,        // Usage (Joystick)
    0xA1, 0x01,        // Collection (Application)
    0x85, 0x02,        //   Report ID (2)
    0x75, 0x04,        //   Report Size (4)
    0x95, 0x01,        //   Report Count (1)
    0x81, 0x03,        //   Input (Constant, Variable)
    0x09, 0x30,        //   Usage (X)
    0x15, 0x00,        //   Logical Minimum (0)
    0x26, 0xFF, 0x03,  //   Logical Maximum (1023)
    0x75, 0x0A,        //   Report Size (10)
    0x95, 0x01,        //   Report Count (1)
    0x81, 0x02,        //   Input (Data, Variable, Absolute)
    0x75, 0x02,        //   Report Size (2)
    0x81, 0x03,        //   Input (Constant, Variable)
    0xC0,              // End Collection
};

// A three-pedal switch in an unnumbered report: buttons 1-3 as bits 0-2 of byte 0, then 5 bits of
// padding. The first button is bit 0 of byte 0.
const std::vector<uint8_t> kButtonDescriptor = {
    0x05, 0x01,  // Usage Page (Generic Desktop)
    0x09, 0x05,  // Usage (Game Pad)
    0xA1, 0x01,  // Collection (Application)
    0x05, 0x09,  //   Usage Page (Button)
    0x19, 0x01,  //   Usage Minimum (1)
    0x29, 0x03,  //   Usage Maximum (3)
    0x15, 0x00,  //   Logical Minimum (0)
    0x25, 0x01,  //   Logical Maximum (1)
    0x75, 0x01,  //   Report Size (1)
    0x95, 0x03,  //   Report Count (3)
    0x81, 0x02,  //   Input (Data, Variable, Absolute)
    0x95, 0x05,  //   Report Count (5)
    0x81, 0x03,  //   Input (Constant, Variable)
    0xC0,        // End Collection
};

// Items that steer the walk: sizes and counts at and past their limits, report ids, push and pop,
// the usages that rank, usage ranges, extreme logical bounds, every kind of main item, long items.
const std::vector<std::vector<uint8_t>> kDescriptorItems = {
    {0x75, 0x00}, {0x75, 0x01}, {0x75, 0x08}, {0x75, 0x20}, {0x75, 0x21}, {0x75, 0xFF},
    {0x95, 0x00}, {0x95, 0x01}, {0x95, 0xFF}, {0x96, 0x00, 0x10}, {0x96, 0x01, 0x10}, {0x97, 0xFF, 0xFF, 0xFF, 0xFF},
    {0x85, 0x00}, {0x85, 0x01}, {0x85, 0xFF}, {0x86, 0x01, 0x01},
    {0xA4}, {0xB4},
    {0x05, 0x01}, {0x05, 0x02}, {0x05, 0x09}, {0x06, 0x00, 0xFF},
    {0x09, 0x30}, {0x09, 0x36}, {0x09, 0x37}, {0x09, 0xC4}, {0x09, 0xC5}, {0x0B, 0xC5, 0x00, 0x02, 0x00},
    {0x19, 0x01}, {0x29, 0xFF}, {0x1A, 0xFF, 0xFF}, {0x29, 0x00}, {0x2B, 0xFF, 0xFF, 0xFF, 0xFF},
    {0x15, 0x00}, {0x15, 0x80}, {0x17, 0x00, 0x00, 0x00, 0x80}, {0x25, 0xFF}, {0x25, 0x7F}, {0x25, 0x00},
    {0x27, 0xFF, 0xFF, 0xFF, 0x7F}, {0x27, 0xFF, 0xFF, 0xFF, 0xFF}, {0x26, 0xFF, 0x03},
    {0x81, 0x02}, {0x81, 0x00}, {0x81, 0x03}, {0x81, 0x06}, {0x82, 0x02, 0x01}, {0x83, 0x02, 0, 0, 0},
    {0x91, 0x02}, {0xB1, 0x02}, {0xA1, 0x01}, {0xC0},
    {0xFE, 0x02, 0x10, 0xAA, 0xBB}, {0xFE, 0xFF, 0x00}, {0xFE}};

// Offsets where short items start, walking by the size bits of each prefix.
std::vector<size_t> itemStarts(const std::vector<uint8_t>& d) {
  std::vector<size_t> starts;
  size_t i = 0;
  while (i < d.size()) {
    starts.push_back(i);
    i += d[i] == 0xFE ? (i + 1 < d.size() ? 3u + d[i + 1] : 1u) : 1u + ((d[i] & 3u) == 3u ? 4u : (d[i] & 3u));
  }
  starts.push_back(d.size());
  return starts;
}

// One descriptor-level change: an item inserted at an item boundary, a run of items repeated or
// dropped, or one item's data rewritten to a boundary value.
void mutateDescriptor(std::vector<uint8_t>& d, std::mt19937& rng) {
  if (test::mutateBytesGeneric(d, rng)) return;
  const std::vector<size_t> starts = itemStarts(d);
  const size_t a = starts[pick(rng, starts.size())];
  switch (rng() % 4) {
    case 0:
    case 1: {
      const std::vector<uint8_t>& item = kDescriptorItems[pick(rng, kDescriptorItems.size())];
      d.insert(d.begin() + std::ptrdiff_t(a), item.begin(), item.end());
      break;
    }
    case 2: {
      const size_t b = starts[pick(rng, starts.size())];
      const size_t lo = std::min(a, b), hi = std::max(a, b);
      const std::vector<uint8_t> run(d.begin() + std::ptrdiff_t(lo), d.begin() + std::ptrdiff_t(hi));
      if (rng() % 2) {
        d.insert(d.begin() + std::ptrdiff_t(pick(rng, d.size() + 1)), run.begin(), run.end());
      } else {
        d.erase(d.begin() + std::ptrdiff_t(lo), d.begin() + std::ptrdiff_t(hi));
      }
      break;
    }
    default: {
      static const uint8_t kData[] = {0x00, 0x01, 0x7F, 0x80, 0xFF};
      for (size_t k = a + 1; k < d.size() && k < a + 5; ++k) d[k] = kData[rng() % std::size(kData)];
      break;
    }
  }
}

// A layout from a descriptor must address a field hidapi can hand over, and decode every report.
void checkDescriptorLayout(const std::optional<PedalLayout>& layout, std::mt19937& rng, int iteration) {
  if (!layout) return;
  const PedalLayout& l = *layout;
  ASSERT_TRUE(l.report_id >= -1 && l.report_id <= 255) << "iteration " << iteration;
  ASSERT_TRUE(l.byte >= 0 && l.byte <= 255) << "iteration " << iteration;
  // A numbered report's id is byte 0, so its fields start at byte 1.
  if (l.report_id >= 0) {
    ASSERT_GE(l.byte, 1) << "iteration " << iteration;
  }
  ASSERT_FALSE(l.invert);
  ASSERT_TRUE(l.dead_band >= 0.0 && l.dead_band < 0.5);
  switch (l.input) {
    case PedalInput::Button: ASSERT_EQ(std::popcount(l.button_mask), 1) << "iteration " << iteration; break;
    case PedalInput::Axis:
      ASSERT_TRUE(l.bit >= 0 && l.bit <= 7) << "iteration " << iteration;
      ASSERT_TRUE(l.bits >= 1 && l.bits <= 32) << "iteration " << iteration;
      ASSERT_NE(l.raw_min, l.raw_max) << "iteration " << iteration;
      break;
    case PedalInput::Key: FAIL() << "a descriptor gave a keyboard layout, iteration " << iteration;
  }
  checkDecodes(l, rng, iteration);
}

TEST(DeviceParsersFuzz, SeedDescriptorsGiveTheirFields) {
  const std::optional<PedalLayout> axis = layoutFromReportDescriptor(kAxisDescriptor);
  ASSERT_TRUE(axis);
  EXPECT_EQ(axis->input, PedalInput::Axis);
  EXPECT_EQ(axis->report_id, 2);
  EXPECT_EQ(axis->byte, 1);
  EXPECT_EQ(axis->bit, 4);
  EXPECT_EQ(axis->bits, 10);
  EXPECT_EQ(axis->raw_min, 0);
  EXPECT_EQ(axis->raw_max, 1023);
  // Raw 677 = 0x2A5 from bit 12: its low nibble 0x5 is the high nibble of byte 1, 0x2A byte 2.
  const std::vector<uint8_t> report = {0x02, 0x50, 0x2A};
  const std::optional<double> v = decodePedalReport(*axis, report);
  ASSERT_TRUE(v);
  EXPECT_DOUBLE_EQ(*v, 677.0 / 1023.0);

  const std::optional<PedalLayout> button = layoutFromReportDescriptor(kButtonDescriptor);
  ASSERT_TRUE(button);
  EXPECT_EQ(button->input, PedalInput::Button);
  EXPECT_EQ(button->report_id, -1);
  EXPECT_EQ(button->byte, 0);
  EXPECT_EQ(button->button_mask, 0x01);
  // Pedal 2 alone is not the first button.
  EXPECT_EQ(decodePedalReport(*button, std::vector<uint8_t>{0x02}), 0.0);
  EXPECT_EQ(decodePedalReport(*button, std::vector<uint8_t>{0x05}), 1.0);
}

// How often each outcome must occur, or the mutations are not exercising the walk [fraction of cases].
struct DescriptorOutcomes {
  double axes = 0;
  double buttons = 0;
  double none = 0;
};

void fuzzDescriptor(const std::vector<uint8_t>& seed, uint32_t rng_seed, int iterations, DescriptorOutcomes least) {
  std::mt19937 rng(rng_seed);
  int axes = 0, buttons = 0, none = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> d = seed;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) mutateDescriptor(d, rng);
    // Exactly the descriptor's bytes, so that a read past its end is caught.
    const std::vector<uint8_t> exact(d.begin(), d.end());
    const std::optional<PedalLayout> layout = layoutFromReportDescriptor(exact);
    checkDescriptorLayout(layout, rng, it);
    if (::testing::Test::HasFatalFailure()) return;
    if (!layout) ++none;
    else if (layout->input == PedalInput::Axis) ++axes;
    else ++buttons;
  }
  EXPECT_GE(axes, least.axes * iterations);
  EXPECT_GE(buttons, least.buttons * iterations);
  EXPECT_GE(none, least.none * iterations);
}

TEST(DeviceParsersFuzz, MutatedAxisDescriptors) {
  fuzzDescriptor(kAxisDescriptor, 4242u, 20000, {.axes = 0.08, .buttons = 0, .none = 0.3});
}

TEST(DeviceParsersFuzz, MutatedButtonDescriptors) {
  fuzzDescriptor(kButtonDescriptor, 99u, 20000, {.axes = 0, .buttons = 0.08, .none = 0.3});
}

// The axis outranks the buttons before it; edits that break it leave the buttons to be found.
TEST(DeviceParsersFuzz, SplicedDescriptors) {
  std::vector<uint8_t> both = kButtonDescriptor;
  both.insert(both.end(), kAxisDescriptor.begin(), kAxisDescriptor.end());
  ASSERT_EQ(layoutFromReportDescriptor(both)->input, PedalInput::Axis);
  fuzzDescriptor(both, 2718u, 20000, {.axes = 0.1, .buttons = 0.08, .none = 0.2});
}

// ---- Falcon byte stream -------------------------------------------------------------------------

using falcon::kPacketSize;
using falcon::Reply;

bool sameReply(const Reply& a, const Reply& b) {
  return a.encoder == b.encoder && a.homed == b.homed && a.grip == b.grip;
}

// The firmware's reply written out by hand: '<', each encoder as four nibbles 'A' + n least
// significant first, 'A' + (homed << 4 | grip), a spare 'A', '>'.
std::vector<uint8_t> replyBytes(const Reply& r) {
  std::vector<uint8_t> p = {'<'};
  for (int16_t e : r.encoder) {
    const auto bits = uint16_t(e);
    for (int k = 0; k < 4; ++k) p.push_back(uint8_t('A' + ((bits >> (4 * k)) & 0xF)));
  }
  p.push_back(uint8_t('A' + (r.homed << 4 | r.grip)));
  p.push_back('A');
  p.push_back('>');
  return p;
}

// The reply 16 bytes hold, read by the rules in falcon_protocol.h: framing, nibble bytes, and a
// status byte of 7 bits above 'A'; nullopt where they break them.
std::optional<Reply> replyIn(const uint8_t* p) {
  if (p[0] != '<' || p[15] != '>') return std::nullopt;
  Reply r;
  for (size_t m = 0; m < 3; ++m) {
    uint16_t bits = 0;
    for (size_t k = 0; k < 4; ++k) {
      const uint8_t b = p[1 + 4 * m + k];
      if (b < 'A' || b > 'P') return std::nullopt;
      bits = uint16_t(bits | (b - 'A') << (4 * k));
    }
    r.encoder[m] = int16_t(bits);
  }
  if (p[13] < 'A' || p[13] >= 'A' + 0x80) return std::nullopt;
  r.homed = uint8_t((p[13] - 'A') >> 4);
  r.grip = uint8_t((p[13] - 'A') & 0xF);
  return r;
}

struct Expected {
  std::vector<Reply> replies;
  std::vector<size_t> ends;  // the stream offset of each reply's last byte
  uint64_t dropped = 0;      // bytes thrown away once the whole stream is in
};

// What an assembler must make of `s`, from its contract alone: every '<' starts a packet, so each
// '<' followed by 15 bytes without another '<' is a packet, decoded if its bytes are valid; all other
// bytes are dropped, except a trailing fragment shorter than a packet, which stays buffered.
Expected expectedReplies(const std::vector<uint8_t>& s) {
  Expected e;
  size_t buffered = 0;
  for (size_t p = 0; p < s.size(); ++p) {
    if (s[p] != '<') continue;
    const size_t next = std::find(s.begin() + std::ptrdiff_t(p) + 1, s.end(), uint8_t('<')) - s.begin();
    if (next - p < kPacketSize) {
      if (next == s.size()) buffered = next - p;
      continue;
    }
    if (const std::optional<Reply> r = replyIn(&s[p])) {
      e.replies.push_back(*r);
      e.ends.push_back(p + kPacketSize - 1);
    }
  }
  e.dropped = s.size() - kPacketSize * e.replies.size() - buffered;
  return e;
}

// A stand-in for "no reply yet": homed and grip out of the packet's range.
Reply sentinel() {
  Reply r;
  r.encoder = {1111, -2222, 3333};
  r.homed = 0xEE;
  r.grip = 0xEE;
  return r;
}

// Replies with encoders at and between their extremes, every homing state and grip bits.
std::vector<Reply> seedReplies(int count, std::mt19937& rng) {
  static const int16_t kEncoders[] = {0, 1, -1, 32767, -32768, 0x1234, -0x1234, 256, -256};
  std::vector<Reply> out;
  for (int i = 0; i < count; ++i) {
    Reply r;
    for (int16_t& e : r.encoder) e = rng() % 2 ? kEncoders[rng() % std::size(kEncoders)] : int16_t(uint16_t(rng()));
    r.homed = uint8_t(rng() % 8);
    r.grip = uint8_t(rng() % 16);
    out.push_back(r);
  }
  return out;
}

std::vector<uint8_t> streamOf(const std::vector<Reply>& replies) {
  std::vector<uint8_t> s;
  for (const Reply& r : replies) {
    const std::vector<uint8_t> p = replyBytes(r);
    s.insert(s.end(), p.begin(), p.end());
  }
  return s;
}

// One stream-level change: stray framing bytes, a packet repeated, dropped or cut, a nibble byte
// just outside 'A'..'P', or a status byte at the edge of its range.
void mutateStream(std::vector<uint8_t>& s, std::mt19937& rng) {
  if (test::mutateBytesGeneric(s, rng)) return;
  const size_t packets = s.size() / kPacketSize;
  switch (rng() % 5) {
    case 0: s.insert(s.begin() + std::ptrdiff_t(pick(rng, s.size() + 1)), rng() % 2 ? uint8_t('<') : uint8_t('>')); break;
    case 1:
      if (packets > 0) {
        const size_t at = pick(rng, packets) * kPacketSize;
        const std::vector<uint8_t> p(s.begin() + std::ptrdiff_t(at), s.begin() + std::ptrdiff_t(at + kPacketSize));
        s.insert(s.begin() + std::ptrdiff_t(pick(rng, packets + 1) * kPacketSize), p.begin(), p.end());
      }
      break;
    case 2:
      if (packets > 0) {
        const size_t at = pick(rng, packets) * kPacketSize;
        s.erase(s.begin() + std::ptrdiff_t(at + 1 + pick(rng, kPacketSize - 1)), s.begin() + std::ptrdiff_t(at + kPacketSize));
      }
      break;
    case 3: {
      static const uint8_t kNearNibbles[] = {'@', 'Q', 'a', 'p', 0x00, 0xC0, 0xC1, 0xBF};
      if (!s.empty()) s[pick(rng, s.size())] = kNearNibbles[rng() % std::size(kNearNibbles)];
      break;
    }
    default:
      if (packets > 0) s[pick(rng, packets) * kPacketSize + 13] = rng() % 2 ? uint8_t('A' + 0x7F) : uint8_t('A' + 0x80);
      break;
  }
}

// Feeding byte by byte gives exactly the expected replies, in order, each well-formed; the bytes
// fed always equal those dropped, decoded and buffered, and never more than one packet is buffered.
void checkByteByByte(const std::vector<uint8_t>& s, const Expected& e, int iteration) {
  falcon::PacketAssembler a;
  Reply latest = sentinel();
  size_t n = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const int got = a.feed(&s[i], 1, &latest);
    ASSERT_TRUE(got == 0 || got == 1) << "iteration " << iteration;
    if (got == 1) {
      ASSERT_LT(n, e.replies.size()) << "iteration " << iteration << ": a reply at byte " << i;
      ASSERT_EQ(e.ends[n], i) << "iteration " << iteration;
      ASSERT_TRUE(sameReply(latest, e.replies[n])) << "iteration " << iteration << ", reply " << n;
      ASSERT_LE(latest.homed, falcon::kAllAxesHomed);
      ASSERT_LE(latest.grip, 0xF);
      ++n;
    }
    const uint64_t fed = i + 1;
    ASSERT_LE(a.droppedBytes() + kPacketSize * n, fed) << "iteration " << iteration;
    ASSERT_LT(fed - a.droppedBytes() - kPacketSize * n, kPacketSize) << "iteration " << iteration << ": buffered too much";
  }
  ASSERT_EQ(n, e.replies.size()) << "iteration " << iteration;
  ASSERT_EQ(a.droppedBytes(), e.dropped) << "iteration " << iteration;
}

// Fed as two pieces split at `k`: each piece returns the replies that end in it and leaves the
// latest of them, and the bytes dropped are the same as for the whole stream.
void checkSplit(const std::vector<uint8_t>& s, const Expected& e, size_t k, int iteration) {
  falcon::PacketAssembler a;
  Reply latest = sentinel();
  const size_t before = size_t(std::lower_bound(e.ends.begin(), e.ends.end(), k) - e.ends.begin());
  const int first = a.feed(s.data(), k, &latest);
  ASSERT_EQ(size_t(first), before) << "iteration " << iteration << ", split at " << k;
  ASSERT_TRUE(sameReply(latest, before > 0 ? e.replies[before - 1] : sentinel())) << "iteration " << iteration << ", split at " << k;
  const int second = a.feed(s.data() + k, s.size() - k, &latest);
  ASSERT_EQ(size_t(second), e.replies.size() - before) << "iteration " << iteration << ", split at " << k;
  ASSERT_TRUE(sameReply(latest, e.replies.empty() ? sentinel() : e.replies.back())) << "iteration " << iteration;
  ASSERT_EQ(a.droppedBytes(), e.dropped) << "iteration " << iteration << ", split at " << k;
}

// The stream in USB packets of at most 64 bytes, each led by the FTDI's two modem status bytes,
// and grouped into bulk transfers: stripping and assembling them gives the same replies.
void checkThroughUsb(const std::vector<uint8_t>& s, const Expected& e, std::mt19937& rng, int iteration) {
  std::vector<std::vector<uint8_t>> transfers;
  size_t at = 0;
  while (at < s.size() || transfers.empty()) {
    std::vector<uint8_t> t;
    const size_t usb_packets = 1 + pick(rng, 4);
    for (size_t u = 0; u < usb_packets; ++u) {
      t.push_back(0x31);  // modem status: CTS, DSR
      t.push_back(0x60);  // line status: transmitter empty
      // The last USB packet of a transfer may be short (even status only); the others are full.
      const size_t room = falcon::kUsbPacketSize - falcon::kModemStatusSize;
      const size_t n = std::min(s.size() - at, u + 1 == usb_packets ? pick(rng, room + 1) : room);
      t.insert(t.end(), s.begin() + std::ptrdiff_t(at), s.begin() + std::ptrdiff_t(at + n));
      at += n;
      if (n < room) break;
    }
    transfers.push_back(std::move(t));
  }
  falcon::PacketAssembler a;
  Reply latest = sentinel();
  std::vector<uint8_t> joined;
  size_t decoded = 0;
  for (const std::vector<uint8_t>& t : transfers) {
    std::vector<uint8_t> payload(t.size());  // the documented worst case: as many bytes as came in
    const size_t n = falcon::stripModemStatus(t.data(), t.size(), payload.data());
    ASSERT_LE(n, t.size());
    payload.resize(n);
    joined.insert(joined.end(), payload.begin(), payload.end());
    const std::vector<uint8_t> exact(payload.begin(), payload.end());
    const int got = a.feed(exact.data(), exact.size(), &latest);
    decoded += size_t(got);
    if (got > 0) {
      ASSERT_TRUE(sameReply(latest, e.replies[decoded - 1])) << "iteration " << iteration;
    }
  }
  ASSERT_EQ(joined, s) << "iteration " << iteration;
  ASSERT_EQ(decoded, e.replies.size()) << "iteration " << iteration;
  ASSERT_EQ(a.droppedBytes(), e.dropped) << "iteration " << iteration;
}

TEST(DeviceParsersFuzz, SeedStreamDecodesEveryReply) {
  std::mt19937 rng(5);
  const std::vector<Reply> replies = seedReplies(12, rng);
  const std::vector<uint8_t> s = streamOf(replies);
  const Expected e = expectedReplies(s);
  ASSERT_EQ(e.replies.size(), replies.size());
  for (size_t i = 0; i < replies.size(); ++i) ASSERT_TRUE(sameReply(e.replies[i], replies[i])) << i;
  EXPECT_EQ(e.dropped, 0u);
  checkByteByByte(s, e, -1);
  for (size_t k = 0; k <= s.size() && !HasFatalFailure(); ++k) checkSplit(s, e, k, -1);
  checkThroughUsb(s, e, rng, -1);
}

TEST(DeviceParsersFuzz, MutatedFalconStreams) {
  std::mt19937 rng(16180u);
  size_t total_replies = 0, total_dropped = 0;
  for (int it = 0; it < 5000; ++it) {
    std::vector<uint8_t> s = streamOf(seedReplies(1 + int(rng() % 10), rng));
    const int edits = 1 + int(rng() % 4);
    for (int m = 0; m < edits; ++m) mutateStream(s, rng);
    const Expected e = expectedReplies(s);
    total_replies += e.replies.size();
    total_dropped += e.dropped;
    checkByteByByte(s, e, it);
    if (HasFatalFailure()) return;
    // Every split point for the first cases; a few random ones after that keep the test quick.
    if (it < 1000) {
      for (size_t k = 0; k <= s.size() && !HasFatalFailure(); ++k) checkSplit(s, e, k, it);
    } else {
      for (int j = 0; j < 4 && !HasFatalFailure(); ++j) checkSplit(s, e, pick(rng, s.size() + 1), it);
    }
    if (HasFatalFailure()) return;
    checkThroughUsb(s, e, rng, it);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(total_replies, 10000u);
  EXPECT_GT(total_dropped, 10000u);
}

TEST(DeviceParsersFuzz, MutatedSinglePackets) {
  std::mt19937 rng(314u);
  int valid = 0, invalid = 0;
  for (int it = 0; it < 20000; ++it) {
    std::vector<uint8_t> p = replyBytes(seedReplies(1, rng)[0]);
    const int edits = 1 + int(rng() % 2);
    for (int m = 0; m < edits; ++m) mutateStream(p, rng);
    p.resize(kPacketSize, uint8_t(rng()));  // decodeStatus reads exactly 16 bytes
    const std::vector<uint8_t> exact(p.begin(), p.end());
    Reply got = sentinel();
    const bool ok = falcon::decodeStatus(exact.data(), &got);
    const std::optional<Reply> want = replyIn(exact.data());
    ASSERT_EQ(ok, want.has_value()) << "iteration " << it;
    if (ok) {
      ++valid;
      ASSERT_TRUE(sameReply(got, *want)) << "iteration " << it;
    } else {
      ++invalid;
      ASSERT_TRUE(sameReply(got, sentinel())) << "iteration " << it << ": a rejected packet wrote the reply";
    }
  }
  EXPECT_GT(valid, 1000);
  EXPECT_GT(invalid, 1000);
}

TEST(DeviceParsersFuzz, MutatedLoaderGreetings) {
  std::mt19937 rng(8u);
  const std::vector<uint8_t> hello(falcon::kLoaderHelloReply.begin(), falcon::kLoaderHelloReply.end());
  std::vector<uint8_t> with_nul = {0x00};
  with_nul.insert(with_nul.end(), hello.begin(), hello.end());
  int yes = 0, no = 0;
  for (int it = 0; it < 20000; ++it) {
    std::vector<uint8_t> r = rng() % 2 ? hello : with_nul;
    if (it >= 2) test::mutateBytesGeneric(r, rng);
    const std::vector<uint8_t> exact(r.begin(), r.end());
    // Byte for byte the greeting LF 'D' ',' CR, or a NUL and then it.
    const bool want = (exact.size() == 4 && exact == hello) ||
                      (exact.size() == 5 && exact[0] == 0x00 && std::equal(hello.begin(), hello.end(), exact.begin() + 1));
    ASSERT_EQ(falcon::isLoaderHelloReply(exact.data(), exact.size()), want) << "iteration " << it;
    (want ? yes : no)++;
  }
  EXPECT_GT(yes, 100);
  EXPECT_GT(no, 1000);
}

TEST(DeviceParsersFuzz, StrippedTransfersOfEverySize) {
  // Each 64-byte USB packet gives up its first two bytes; a packet of two bytes or fewer gives none.
  std::mt19937 rng(64u);
  for (size_t size = 0; size <= 4 * falcon::kUsbPacketSize + 3; ++size) {
    std::vector<uint8_t> t(size);
    for (uint8_t& b : t) b = uint8_t(rng());
    std::vector<uint8_t> want;
    for (size_t at = 0; at < size; at += 64)
      for (size_t k = at + 2; k < std::min(size, at + 64); ++k) want.push_back(t[k]);
    std::vector<uint8_t> out(size);
    const size_t n = falcon::stripModemStatus(t.data(), t.size(), out.data());
    out.resize(n);
    ASSERT_EQ(out, want) << "transfer of " << size << " bytes";
  }
}

}  // namespace
}  // namespace dentsim::devices
