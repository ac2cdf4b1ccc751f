// Session file (.dses) reading and writing: a JSON header, then records checksummed one by one so that a crash mid-write loses only the last record.
//
// Contents
//   1. Layout constants and little-endian byte helpers
//   2. Header JSON: writing, and reading with every key and type checked
//   3. Record encoding (shared by SessionWriter and encodeSession)
//   4. Reader: framing (checksums, truncation), then one check per record kind
//   5. readSessionFile, parseSession
//   6. SessionWriter
//   7. encodeSession
#include "io/session_file.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ctime>
#include <functional>
#include <limits>
#include <set>
#include <string_view>

#include <nlohmann/json.hpp>
#include <xxhash.h>

#include "io/atomic_file.h"
#include "io/parse_guard.h"
#include "io/pen_path_file.h"

namespace dentsim {
namespace {

// ---- 1. layout ------------------------------------------------------------------------------

static_assert(std::endian::native == std::endian::little, ".dses stores little-endian words as they are in memory");

constexpr char kMagic[8] = {'D', 'S', 'E', 'S', 'S', 'I', 'O', 'N'};
constexpr std::string_view kHeaderFormat = "dentsim-session";

constexpr size_t kPreambleBytes = 16;   // magic, version, header length [B]
constexpr size_t kHeaderHashBytes = 8;  // XXH64 of the header text [B]
constexpr size_t kFrameBytes = 8;       // kind, three zero bytes, payload length [B]
constexpr size_t kRecordHashBytes = 4;  // XXH32 of frame and payload [B]

enum RecordKind : uint8_t {
  kStepRecord = 1,
  kParamsRecord = 2,
  kGapRecord = 3,
  kEndRecord = 4,
  kDeviceRecord = 5,
  kScheduleRecord = 6,  // right after the step record of a step whose SessionSchedule is not the default
};

constexpr size_t kPenCount = 2;
constexpr size_t kStepFixedBytes = 8 + 8 + 4 + 1;            // step, wall_ns, params_serial, pens
constexpr size_t kPenReadingBytes = 13 * 8 + 4 + 8;          // pose, velocities (13 f64), buttons, pedal
constexpr size_t kStepOutputBytes = kPenCount * (3 * 8 + 4); // force_n and contacts of both pens
constexpr size_t kParamsFixedBytes = 4 + 8;                  // serial, from_step
constexpr size_t kGapBytes = 8 + 8;                          // first_step, steps
constexpr size_t kEndFixedBytes = 8 + 2 + 2;                 // steps and the two string lengths
constexpr size_t kDeviceFixedBytes = 8 + 1 + 2 + 2;          // step, pen and the two string lengths
constexpr size_t kScheduleBytes = 8 + kPenCount * 4 + 4;     // step, clusters of both pens, cuts
constexpr size_t kMaxDeviceStateBytes = 32;
constexpr size_t kHashHexDigits = 16;
constexpr size_t kMaxReasonBytes = 200;
constexpr uint8_t kPenBits = 0b11;
// Step indices stay below 2^63, so that "the next step" never overflows.
constexpr uint64_t kStepIndexEnd = uint64_t{1} << 63;

constexpr double kMinRateHz = 100.0, kMaxRateHz = 10000.0;
constexpr int kMinToothLevel = 3, kMaxToothLevel = 12;

size_t stepPayloadBytes(uint8_t pens) {
  return kStepFixedBytes + kStepOutputBytes + size_t(std::popcount(unsigned(pens & kPenBits))) * kPenReadingBytes;
}

template <class T>
void append(std::vector<uint8_t>& out, T v) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));  // within capacity once the buffer has grown: no allocation
  std::memcpy(out.data() + at, &v, sizeof(T));
}

void appendBytes(std::vector<uint8_t>& out, std::string_view bytes) {
  const size_t at = out.size();
  out.resize(at + bytes.size());
  if (!bytes.empty()) std::memcpy(out.data() + at, bytes.data(), bytes.size());
}

template <class T>
T get(std::span<const uint8_t> in, size_t at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  return v;
}

// Reads a payload front to back; the caller has checked its length first.
class Cursor {
 public:
  explicit Cursor(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  template <class T>
  T next() {
    assert(at_ + sizeof(T) <= bytes_.size());
    const T v = get<T>(bytes_, at_);
    at_ += sizeof(T);
    return v;
  }
  std::string_view text(size_t n) {
    assert(at_ + n <= bytes_.size());
    const std::string_view s(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return s;
  }
  size_t left() const { return bytes_.size() - at_; }
  // The payload's last two fields, each a u16 length and its bytes, which must use up the rest
  // exactly (the end and device records close this way). False when they do not.
  bool lastTwoTexts(std::string* first, std::string* second) {
    if (left() < 2) return false;
    const uint16_t first_bytes = next<uint16_t>();
    if (left() < size_t(first_bytes) + 2) return false;
    first->assign(text(first_bytes));
    const uint16_t second_bytes = next<uint16_t>();
    if (left() != second_bytes) return false;
    second->assign(text(second_bytes));
    return true;
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
};

// The shortest text that reads back to the same double.
std::string numberText(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  assert(ec == std::errc());
  return std::string(buf, end);
}

bool isLowerHex(std::string_view s, size_t digits) {
  return s.size() == digits &&
         std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

bool isPrintableAscii(std::string_view s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
}

// ---- 2. header JSON -------------------------------------------------------------------------

// ordered_json keeps keys in file order, so the parameter set reads back in the order sim wrote it.
using Json = nlohmann::ordered_json;

// The header's keys; every one is required and no other is allowed.
constexpr const char* kRootKeys[] = {"format", "version", "created_utc", "program", "rate_hz",
                                     "task",   "tooth",   "tools",       "params"};
constexpr const char* kToothKeys[] = {"hash", "file", "source", "level", "voxel_mm"};
constexpr const char* kToolKeys[] = {"drill", "mirror"};

// The parameter set as a JSON value: the object itself, or null when the text is not JSON (the
// reader then refuses the file instead of the writer silently dropping the parameters).
Json paramsValue(const std::string& params_json) {
  Json v = Json::parse(params_json, nullptr, false);
  return v.is_discarded() ? Json(nullptr) : v;
}

std::string headerText(const SessionInfo& info) {
  Json tooth = Json::object();
  tooth["hash"] = info.tooth_hash;
  tooth["file"] = info.tooth_file;
  tooth["source"] = info.tooth_source;
  tooth["level"] = info.tooth_level;
  tooth["voxel_mm"] = info.voxel_mm;
  Json tools = Json::object();
  tools["drill"] = info.drill_tool;
  tools["mirror"] = info.mirror_tool;
  Json h = Json::object();
  h["format"] = kHeaderFormat;
  h["version"] = kSessionFileVersion;
  h["created_utc"] = info.created_utc;
  h["program"] = info.program;
  h["rate_hz"] = info.rate_hz;
  h["task"] = info.task;
  h["tooth"] = std::move(tooth);
  h["tools"] = std::move(tools);
  h["params"] = paramsValue(info.params_json);
  if (!info.guide_json.empty()) h["guide"] = paramsValue(info.guide_json);
  // nlohmann prints doubles so that they read back to the same bits; invalid UTF-8 in a string
  // becomes U+FFFD rather than an exception.
  return h.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

// What the reader checks of the values once their types are right; open() checks the same, so the
// writer never starts a file that would not load. Returns "<field>: <problem>".
std::optional<std::string> checkInfoValues(const SessionInfo& info) {
  if (!std::isfinite(info.rate_hz) || info.rate_hz < kMinRateHz || info.rate_hz > kMaxRateHz)
    return "rate_hz: " + numberText(info.rate_hz) + " Hz is outside [100, 10000]";
  if (!isLowerHex(info.tooth_hash, kHashHexDigits))
    return "tooth.hash: " + quoteToken(info.tooth_hash) + " is not 16 lower-case hex digits";
  if (info.tooth_level < kMinToothLevel || info.tooth_level > kMaxToothLevel)
    return "tooth.level: " + std::to_string(info.tooth_level) + " is outside [3, 12]";
  if (!std::isfinite(info.voxel_mm) || !(info.voxel_mm > 0.0))
    return "tooth.voxel_mm: " + numberText(info.voxel_mm) + " mm is not a finite size > 0";
  if (info.drill_tool.empty()) return "tools.drill: empty (the drill pen always carries a tool)";
  return std::nullopt;
}

// "string \"abc\"", "number 1.5", "object": what a value was, for a message.
std::string describe(const Json& v) {
  if (v.is_string()) return "string " + quoteToken(v.get_ref<const std::string&>(), 40);
  if (v.is_number() || v.is_boolean()) return std::string(v.type_name()) + " " + v.dump();
  return v.type_name();
}

// Watches nlohmann's parse of the header for what its tree would hide or cannot bear: duplicate keys,
// which it would silently collapse to the last one (checked in the root object and in "tooth" and
// "tools"; the parameter set is sim's to judge), and nesting deeper than kMaxHeaderDepth, which its
// recursive dump() could not print without exhausting the stack. Too deep a value is dropped as it
// is read, so it costs no memory.
constexpr int kMaxHeaderDepth = 64;

class HeaderWatch {
 public:
  // `depth` is nlohmann's: the root object starts at 0, its keys are at 1, an object in it starts at 1.
  bool operator()(int depth, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    if (event == E::object_start || event == E::array_start) {
      if (depth >= kMaxHeaderDepth) {
        too_deep_ = true;
        return false;
      }
      if (event == E::object_start && depth <= 1) keys_[size_t(depth)].clear();
    } else if (event == E::key && depth >= 1 && depth <= 2 && duplicate_.empty()) {
      const std::string& k = parsed.get_ref<const std::string&>();
      if (depth == 1) root_key_ = k;
      const bool checked = depth == 1 || root_key_ == "tooth" || root_key_ == "tools";
      if (checked && !keys_[size_t(depth - 1)].insert(k).second)
        duplicate_ = depth == 1 ? quoteToken(k) : root_key_ + "." + quoteToken(k);
    }
    return true;
  }
  // The problem found, or empty.
  std::string problem() const {
    if (too_deep_) return "nested deeper than " + std::to_string(kMaxHeaderDepth) + " levels";
    if (!duplicate_.empty()) return "duplicate key " + duplicate_;
    return {};
  }

 private:
  std::set<std::string> keys_[2];  // keys seen in the root object and in the object being read in it
  std::string root_key_;           // the root key whose value is being read
  std::string duplicate_;          // the first duplicate found, as a message names it
  bool too_deep_ = false;
};

// Checks that `obj` holds exactly `keys`. `name` names the object in messages ("tooth"), empty for
// the root.
template <size_t N>
std::optional<std::string> checkKeys(const Json& obj, const char* const (&keys)[N], const std::string& name) {
  const std::string prefix = name.empty() ? "" : name + ": ";
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if (std::none_of(std::begin(keys), std::end(keys), [&k](const char* known) { return k == known; }))
      return prefix + "unknown key " + quoteToken(k);
  }
  for (const char* k : keys)
    if (!obj.contains(k)) return prefix + "missing key " + quoteToken(k);
  return std::nullopt;
}

std::optional<std::string> getString(const Json& obj, const char* key, const std::string& prefix, std::string& out) {
  const Json& v = obj.at(key);
  if (!v.is_string()) return prefix + key + ": expected a string, found " + describe(v);
  out = v.get<std::string>();
  return std::nullopt;
}

std::optional<std::string> getNumber(const Json& obj, const char* key, const std::string& prefix, double& out) {
  const Json& v = obj.at(key);
  if (!v.is_number()) return prefix + key + ": expected a number, found " + describe(v);
  out = v.get<double>();
  return std::nullopt;
}

// A JSON integer (no fraction, no exponent) in [lo, hi].
std::optional<std::string> getInteger(const Json& obj, const char* key, const std::string& prefix, int64_t lo,
                                      int64_t hi, int64_t& out) {
  const Json& v = obj.at(key);
  const std::string range =
      lo == hi ? std::to_string(lo) : "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const bool in_range = (v.is_number_unsigned() && v.get<uint64_t>() <= uint64_t(hi) && int64_t(v.get<uint64_t>()) >= lo) ||
                        (v.is_number_integer() && !v.is_number_unsigned() && v.get<int64_t>() >= lo && v.get<int64_t>() <= hi);
  if (!in_range) return prefix + key + ": expected " + range + ", found " + describe(v);
  out = v.get<int64_t>();
  return std::nullopt;
}

// Parses and checks the header text into `info`; returns the problem, without "header: ".
std::optional<std::string> readHeaderJson(std::string_view text, SessionInfo& info) {
  HeaderWatch watch;
  Json h;
  try {
    h = Json::parse(text.begin(), text.end(), std::ref(watch));
  } catch (const Json::exception& e) {
    // what() reads "[json.exception.parse_error.101] parse error at line 2, ..."; the tag means
    // nothing to a user. A number beyond the double range arrives here too (out_of_range.406).
    std::string_view what = e.what();
    if (const size_t tag_end = what.find("] "); tag_end != what.npos) what.remove_prefix(tag_end + 2);
    const std::string clean = quoteToken(what, 240);
    return "not valid JSON: " + clean.substr(1, clean.size() - 2);
  }
  if (std::string p = watch.problem(); !p.empty()) return p;
  if (!h.is_object()) return "expected a JSON object, found " + describe(h);
  // "guide" is the one optional key: only a guided session has it.
  if (auto g = h.find("guide"); g != h.end()) {
    if (!g->is_object()) return "guide: expected an object (the guide's spring and path), found " + describe(*g);
    info.guide_json = g->dump(-1, ' ', false, Json::error_handler_t::replace);
    h.erase(g);
  }
  if (auto p = checkKeys(h, kRootKeys, "")) return p;

  const Json& format = h.at("format");
  if (!format.is_string() || format.get<std::string>() != kHeaderFormat)
    return "format: expected " + quoteToken(kHeaderFormat) + ", found " + describe(format);
  int64_t version = 0;
  if (auto p = getInteger(h, "version", "", kSessionFileVersion, kSessionFileVersion, version)) return p;
  if (auto p = getString(h, "created_utc", "", info.created_utc)) return p;
  if (auto p = getString(h, "program", "", info.program)) return p;
  if (auto p = getNumber(h, "rate_hz", "", info.rate_hz)) return p;
  if (auto p = getString(h, "task", "", info.task)) return p;

  const Json& tooth = h.at("tooth");
  if (!tooth.is_object()) return "tooth: expected an object, found " + describe(tooth);
  if (auto p = checkKeys(tooth, kToothKeys, "tooth")) return p;
  int64_t level = 0;
  if (auto p = getString(tooth, "hash", "tooth.", info.tooth_hash)) return p;
  if (auto p = getString(tooth, "file", "tooth.", info.tooth_file)) return p;
  if (auto p = getString(tooth, "source", "tooth.", info.tooth_source)) return p;
  if (auto p = getInteger(tooth, "level", "tooth.", kMinToothLevel, kMaxToothLevel, level)) return p;
  info.tooth_level = int(level);
  if (auto p = getNumber(tooth, "voxel_mm", "tooth.", info.voxel_mm)) return p;

  const Json& tools = h.at("tools");
  if (!tools.is_object()) return "tools: expected an object, found " + describe(tools);
  if (auto p = checkKeys(tools, kToolKeys, "tools")) return p;
  if (auto p = getString(tools, "drill", "tools.", info.drill_tool)) return p;
  if (auto p = getString(tools, "mirror", "tools.", info.mirror_tool)) return p;

  const Json& params = h.at("params");
  if (!params.is_object()) return "params: expected an object (the parameter set), found " + describe(params);
  info.params_json = params.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
  return checkInfoValues(info);
}

// ---- 3. record encoding ---------------------------------------------------------------------

// Appends kind, zero bytes, length, the payload and the checksum of all four.
void appendRecord(std::vector<uint8_t>& out, uint8_t kind, std::span<const uint8_t> payload) {
  assert(payload.size() <= std::numeric_limits<uint32_t>::max());
  const size_t start = out.size();
  append<uint8_t>(out, kind);
  append<uint8_t>(out, 0);
  append<uint16_t>(out, 0);
  append<uint32_t>(out, uint32_t(payload.size()));
  const size_t at = out.size();
  out.resize(at + payload.size());
  if (!payload.empty()) std::memcpy(out.data() + at, payload.data(), payload.size());
  append<uint32_t>(out, XXH32(out.data() + start, kFrameBytes + payload.size(), 0));
}

void appendVec3(std::vector<uint8_t>& out, const Vec3& v) {
  append<double>(out, v.x);
  append<double>(out, v.y);
  append<double>(out, v.z);
}

// The payloads, into `p` (cleared first, so its capacity is reused).
void encodeStep(std::vector<uint8_t>& p, const SessionStep& s) {
  p.clear();
  append<uint64_t>(p, s.step);
  append<int64_t>(p, s.wall_ns);
  append<uint32_t>(p, s.params_serial);
  append<uint8_t>(p, s.pens);
  for (size_t r = 0; r < kPenCount; ++r) {
    if (!s.hasReading(r)) continue;
    const SessionPenReading& pen = s.reading[r];
    const Quat& q = pen.grip.rotation;
    appendVec3(p, pen.grip.position);
    for (double v : {q.w, q.x, q.y, q.z}) append<double>(p, v);
    appendVec3(p, pen.velocity);
    appendVec3(p, pen.angular_velocity);
    append<uint32_t>(p, pen.buttons);
    append<double>(p, pen.pedal);
  }
  for (size_t r = 0; r < kPenCount; ++r) {
    appendVec3(p, s.force_n[r]);
    append<uint32_t>(p, s.contacts[r]);
  }
}

void encodeSchedule(std::vector<uint8_t>& p, uint64_t step, const SessionSchedule& schedule) {
  p.clear();
  append<uint64_t>(p, step);
  for (size_t r = 0; r < kPenCount; ++r) append<uint32_t>(p, schedule.clusters[r]);
  append<uint32_t>(p, schedule.cuts);
}

void encodeParams(std::vector<uint8_t>& p, const SessionParams& params) {
  p.clear();
  append<uint32_t>(p, params.serial);
  append<uint64_t>(p, params.from_step);
  appendBytes(p, params.params_json);
}

void encodeGap(std::vector<uint8_t>& p, const SessionGap& gap) {
  p.clear();
  append<uint64_t>(p, gap.first_step);
  append<uint64_t>(p, gap.steps);
}

void encodeDevice(std::vector<uint8_t>& p, const SessionDeviceEvent& event) {
  constexpr size_t kMaxString = 0xffff;  // 16-bit lengths; the reader refuses long ones anyway
  const std::string_view state = std::string_view(event.state).substr(0, kMaxString);
  const std::string_view reason = std::string_view(event.reason).substr(0, kMaxString);
  p.clear();
  append<uint64_t>(p, event.step);
  append<uint8_t>(p, event.pen);
  append<uint16_t>(p, uint16_t(state.size()));
  appendBytes(p, state);
  append<uint16_t>(p, uint16_t(reason.size()));
  appendBytes(p, reason);
}

void encodeEnd(std::vector<uint8_t>& p, const SessionEnd& end) {
  // Lengths are 16 bits; longer strings (which the reader refuses anyway) are cut to fit.
  constexpr size_t kMaxString = 0xffff;
  const std::string_view hash = std::string_view(end.final_hash).substr(0, kMaxString);
  const std::string_view reason = std::string_view(end.reason).substr(0, kMaxString);
  p.clear();
  append<uint64_t>(p, end.steps);
  append<uint16_t>(p, uint16_t(hash.size()));
  appendBytes(p, hash);
  append<uint16_t>(p, uint16_t(reason.size()));
  appendBytes(p, reason);
}

void appendHeader(std::vector<uint8_t>& out, const SessionInfo& info) {
  const std::string text = headerText(info);
  assert(text.size() <= std::numeric_limits<uint32_t>::max());
  appendBytes(out, std::string_view(kMagic, sizeof kMagic));
  append<uint32_t>(out, kSessionFileVersion);
  append<uint32_t>(out, uint32_t(text.size()));
  appendBytes(out, text);
  append<uint64_t>(out, XXH64(text.data(), text.size(), 0));
}

// ---- 4. reader ------------------------------------------------------------------------------

class SessionParser {
 public:
  SessionParser(std::span<const uint8_t> bytes, const std::string& where, const SessionReadLimits& limits)
      : in_(bytes), where_(where), limits_(limits) {}

  Result<SessionRecording> parse() {
    if (std::optional<Error> e = readHeader()) return *e;
    while (pos_ < in_.size()) {
      ++record_;
      if (rec_.end) return fail("data after the end record");
      const size_t left = in_.size() - pos_;
      if (left < kFrameBytes) return truncated();
      const uint32_t length = get<uint32_t>(in_, pos_ + 4);
      if (length > limits_.max_record_bytes)
        return fail("payload of " + std::to_string(length) + " bytes exceeds the limit of " +
                    std::to_string(limits_.max_record_bytes) + " bytes");
      const size_t record_bytes = kFrameBytes + size_t(length) + kRecordHashBytes;
      if (left < record_bytes) return truncated();
      const uint32_t stored = get<uint32_t>(in_, pos_ + kFrameBytes + length);
      if (stored != XXH32(in_.data() + pos_, kFrameBytes + length, 0)) {
        // A crash can leave the last record half written; anywhere else the file is damaged.
        if (left == record_bytes) return truncated();
        return fail("checksum mismatch: the file is corrupt");
      }
      if (in_[pos_ + 1] != 0 || in_[pos_ + 2] != 0 || in_[pos_ + 3] != 0)
        return fail("the three bytes after the record kind are not zero");
      const std::span<const uint8_t> payload = in_.subspan(pos_ + kFrameBytes, length);
      std::optional<std::string> problem;
      switch (in_[pos_]) {
        case kStepRecord: problem = readStep(payload); break;
        case kParamsRecord: problem = readParams(payload); break;
        case kGapRecord: problem = readGap(payload); break;
        case kEndRecord: problem = readEnd(payload); break;
        case kDeviceRecord: problem = readDevice(payload); break;
        case kScheduleRecord: problem = readSchedule(payload); break;
        default: problem = "unknown record kind " + std::to_string(in_[pos_]);
      }
      if (problem) return fail(*problem);
      last_kind_ = in_[pos_];
      pos_ += record_bytes;
    }
    return std::move(rec_);
  }

 private:
  // Where the next step's index is known from: nothing yet, the last step, a gap, or a parameter
  // set read before any step or gap (its from_step names the next step).
  enum class Anchor { None, Step, Gap, Params };

  std::optional<Error> readHeader();
  std::optional<std::string> readStep(std::span<const uint8_t> payload);
  std::optional<std::string> readDevice(std::span<const uint8_t> payload);
  std::optional<std::string> readPen(Cursor& c, size_t r, SessionPenReading& pen);
  std::optional<std::string> readParams(std::span<const uint8_t> payload);
  std::optional<std::string> readGap(std::span<const uint8_t> payload);
  std::optional<std::string> readEnd(std::span<const uint8_t> payload);
  std::optional<std::string> readSchedule(std::span<const uint8_t> payload);
  std::optional<std::string> checkNext(const std::string& what, uint64_t index) const;
  std::string lastRecord() const;

  // "<where>: record <n> at byte <b>: <what>"
  Error fail(const std::string& what) const {
    return makeError(where_, "record " + std::to_string(record_) + " at byte " + std::to_string(pos_) + ": " + what);
  }
  // The file ends inside record_: keep what came before it.
  SessionRecording truncated() {
    rec_.truncation_warning = where_ + ": cut off at byte " + std::to_string(in_.size()) + " inside record " +
                              std::to_string(record_) + " (which starts at byte " + std::to_string(pos_) +
                              "); read " + std::to_string(rec_.steps.size()) + " steps";
    return std::move(rec_);
  }

  std::span<const uint8_t> in_;
  const std::string& where_;
  const SessionReadLimits& limits_;
  SessionRecording rec_;
  size_t pos_ = 0;         // start of the record being read [B]
  uint64_t record_ = 0;    // records are numbered from 1, the first after the header
  Anchor anchor_ = Anchor::None;
  uint64_t next_step_ = 0;  // the index the next step or gap must have, unless anchor_ is None
  uint8_t last_kind_ = 0;   // RecordKind of the record read last; 0: none yet (a schedule's anchor)
};

std::optional<Error> SessionParser::readHeader() {
  const auto notSession = [&](const std::string& why) {
    return makeError(where_, "is not a dentsim session file (" + why + ")");
  };
  const size_t n = in_.size();
  if (n < sizeof kMagic) {
    if (n > 0 && std::memcmp(in_.data(), kMagic, n) == 0)
      return makeError(where_, "cut off at byte " + std::to_string(n) + " inside the header");
    return notSession(n == 0 ? "empty" : "only " + std::to_string(n) + " bytes");
  }
  if (std::memcmp(in_.data(), kMagic, sizeof kMagic) != 0) return notSession("no DSESSION magic");
  if (n < kPreambleBytes) return makeError(where_, "cut off at byte " + std::to_string(n) + " inside the header");
  const uint32_t version = get<uint32_t>(in_, 8);
  if (version != kSessionFileVersion)
    return makeError(where_, "unsupported session file version " + std::to_string(version) + " (this dentsim reads " +
                                 std::to_string(kSessionFileVersion) + ")");
  const uint32_t header_bytes = get<uint32_t>(in_, 12);
  if (header_bytes > limits_.max_header_bytes)
    return makeError(where_, "header of " + std::to_string(header_bytes) + " bytes exceeds the limit of " +
                                 std::to_string(limits_.max_header_bytes) + " bytes");
  const size_t end = kPreambleBytes + size_t(header_bytes) + kHeaderHashBytes;
  if (n < end)
    return makeError(where_, "cut off at byte " + std::to_string(n) + " inside the header (" + std::to_string(end) +
                                 " bytes)");
  const uint8_t* text = in_.data() + kPreambleBytes;
  if (get<uint64_t>(in_, kPreambleBytes + header_bytes) != XXH64(text, header_bytes, 0))
    return makeError(where_, "header checksum mismatch: the file is corrupt");
  if (std::optional<std::string> p =
          readHeaderJson(std::string_view(reinterpret_cast<const char*>(text), header_bytes), rec_.info))
    return makeError(where_, "header: " + *p);
  pos_ = end;
  return std::nullopt;
}

// Checks that a step or gap starting at `index` may come next. `what` names it ("step 40").
std::optional<std::string> SessionParser::checkNext(const std::string& what, uint64_t index) const {
  if (index >= kStepIndexEnd) return what + ": step index beyond 2^63 - 1";
  if (anchor_ == Anchor::None || index == next_step_) return std::nullopt;
  switch (anchor_) {
    case Anchor::Step: return what + " follows step " + std::to_string(next_step_ - 1);
    case Anchor::Gap: {
      const SessionGap& g = rec_.gaps.back();
      return what + " follows a gap of " + std::to_string(g.steps) + " steps from step " + std::to_string(g.first_step) +
             " (expected " + std::to_string(next_step_) + ")";
    }
    default:
      return what + " follows params serial " + std::to_string(rec_.params.back().serial) + ", which begins at step " +
             std::to_string(next_step_);
  }
}

// The record read last, as a message names it ("step 11's record", "params serial 2"); only its numbers
// come from the file.
std::string SessionParser::lastRecord() const {
  switch (last_kind_) {
    case kStepRecord: return "step " + std::to_string(rec_.steps.back().step) + "'s record";
    case kScheduleRecord: return "step " + std::to_string(rec_.steps.back().step) + "'s schedule";
    case kParamsRecord: return "params serial " + std::to_string(rec_.params.back().serial);
    case kGapRecord: return "a gap from step " + std::to_string(rec_.gaps.back().first_step);
    case kDeviceRecord: return "a device event at step " + std::to_string(rec_.devices.back().step);
    case kEndRecord: return "the end record";
    default: return "the header";
  }
}

std::optional<std::string> SessionParser::readPen(Cursor& c, size_t r, SessionPenReading& pen) {
  const std::string name = "pen " + std::to_string(r) + (r == 0 ? " (drill) " : " (mirror) ");
  const auto vec3 = [&](const char* field, Vec3& v) -> std::optional<std::string> {
    for (int a = 0; a < 3; ++a) {
      v[a] = c.next<double>();
      if (!std::isfinite(v[a]))
        return name + field + "[" + std::to_string(a) + "]: not finite (" + numberText(v[a]) + ")";
    }
    return std::nullopt;
  };
  if (auto p = vec3("position", pen.grip.position)) return p;
  Quat& q = pen.grip.rotation;
  double* const parts[] = {&q.w, &q.x, &q.y, &q.z};
  for (size_t a = 0; a < 4; ++a) {
    *parts[a] = c.next<double>();
    if (!std::isfinite(*parts[a]))
      return name + "rotation[" + std::to_string(a) + "]: not finite (" + numberText(*parts[a]) + ")";
  }
  if (auto p = vec3("velocity", pen.velocity)) return p;
  if (auto p = vec3("angular_velocity", pen.angular_velocity)) return p;
  pen.buttons = c.next<uint32_t>();
  pen.pedal = c.next<double>();

  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(std::fabs(n - 1.0) <= kPenRotationNormTolerance))
    return name + "rotation: norm " + numberText(n) + " is not within " + numberText(kPenRotationNormTolerance) +
           " of 1 (not a unit quaternion)";
  // As the pen path readers do: a rotation unit to rounding keeps its bits, so reading, writing
  // and reading again changes nothing.
  constexpr double kUnitSlack = 8 * std::numeric_limits<double>::epsilon();
  if (std::fabs(n - 1.0) > kUnitSlack) q = Quat{q.w / n, q.x / n, q.y / n, q.z / n};
  if (!std::isfinite(pen.pedal)) return name + "pedal: not finite (" + numberText(pen.pedal) + ")";
  if (!(pen.pedal >= 0.0 && pen.pedal <= 1.0)) return name + "pedal: " + numberText(pen.pedal) + " is outside [0, 1]";
  return std::nullopt;
}

std::optional<std::string> SessionParser::readStep(std::span<const uint8_t> payload) {
  if (payload.size() < kStepFixedBytes)
    return "step payload of " + std::to_string(payload.size()) + " bytes is shorter than " +
           std::to_string(kStepFixedBytes);
  Cursor c(payload);
  SessionStep s;
  s.step = c.next<uint64_t>();
  s.wall_ns = c.next<int64_t>();
  s.params_serial = c.next<uint32_t>();
  s.pens = c.next<uint8_t>();
  const std::string what = "step " + std::to_string(s.step);
  if ((s.pens & ~kPenBits) != 0)
    return what + ": pens " + std::to_string(s.pens) + " has bits other than 0 (drill) and 1 (mirror) set";
  if (payload.size() != stepPayloadBytes(s.pens))
    return what + ": payload of " + std::to_string(payload.size()) + " bytes, expected " +
           std::to_string(stepPayloadBytes(s.pens)) + " for pens " + std::to_string(s.pens);
  if (auto p = checkNext(what, s.step)) return p;
  if (s.params_serial > rec_.params.size())
    return what + ": params serial " + std::to_string(s.params_serial) + " was not read before it (the last is " +
           std::to_string(rec_.params.size()) + ")";
  for (size_t r = 0; r < kPenCount; ++r)
    if (s.hasReading(r))
      if (auto p = readPen(c, r, s.reading[r])) return what + ": " + *p;
  for (size_t r = 0; r < kPenCount; ++r) {
    for (int a = 0; a < 3; ++a) {
      s.force_n[r][a] = c.next<double>();
      if (!std::isfinite(s.force_n[r][a]))
        return what + ": pen " + std::to_string(r) + " force_n[" + std::to_string(a) + "]: not finite (" +
               numberText(s.force_n[r][a]) + ")";
    }
    s.contacts[r] = c.next<uint32_t>();
  }
  assert(c.left() == 0);
  if (rec_.steps.size() >= limits_.max_steps)
    return "more than " + std::to_string(limits_.max_steps) + " steps, the limit for one session";
  rec_.steps.push_back(s);
  anchor_ = Anchor::Step;
  next_step_ = s.step + 1;
  return std::nullopt;
}

std::optional<std::string> SessionParser::readParams(std::span<const uint8_t> payload) {
  if (payload.size() < kParamsFixedBytes)
    return "params payload of " + std::to_string(payload.size()) + " bytes is shorter than " +
           std::to_string(kParamsFixedBytes);
  Cursor c(payload);
  SessionParams p;
  p.serial = c.next<uint32_t>();
  p.from_step = c.next<uint64_t>();
  const std::string what = "params serial " + std::to_string(p.serial);
  const uint64_t expected = rec_.params.size() + 1;
  if (p.serial != expected)
    return what + ": expected serial " + std::to_string(expected) +
           (rec_.params.empty() ? " (the first)" : " (after " + std::to_string(rec_.params.size()) + ")");
  if (auto problem = checkNext(what + " from step " + std::to_string(p.from_step), p.from_step)) return problem;
  const std::string_view text = c.text(c.left());
  // accept() runs nlohmann's iterative parser without building a tree.
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == text.npos || text[first] != '{' || !Json::accept(text.begin(), text.end()))
    return what + ": the parameter set is not a JSON object";
  p.params_json.assign(text);
  rec_.params.push_back(std::move(p));
  if (anchor_ == Anchor::None) {
    anchor_ = Anchor::Params;
    next_step_ = rec_.params.back().from_step;
  }
  return std::nullopt;
}

std::optional<std::string> SessionParser::readGap(std::span<const uint8_t> payload) {
  if (payload.size() != kGapBytes)
    return "gap payload of " + std::to_string(payload.size()) + " bytes, expected " + std::to_string(kGapBytes);
  Cursor c(payload);
  SessionGap g;
  g.first_step = c.next<uint64_t>();
  g.steps = c.next<uint64_t>();
  const std::string what = "gap from step " + std::to_string(g.first_step);
  if (g.steps == 0) return what + ": no steps";
  if (auto p = checkNext(what, g.first_step)) return p;
  if (g.steps > kStepIndexEnd - g.first_step) return what + ": " + std::to_string(g.steps) + " steps run past 2^63";
  rec_.gaps.push_back(g);
  anchor_ = Anchor::Gap;
  next_step_ = g.first_step + g.steps;
  return std::nullopt;
}

// A device event does not move the step anchor: it says when, relative to the steps, and nothing more.
std::optional<std::string> SessionParser::readDevice(std::span<const uint8_t> payload) {
  const auto bad_length = [&] {
    return "device payload of " + std::to_string(payload.size()) + " bytes does not match its string lengths";
  };
  if (payload.size() < kDeviceFixedBytes) return bad_length();
  Cursor c(payload);
  SessionDeviceEvent e;
  e.step = c.next<uint64_t>();
  e.pen = c.next<uint8_t>();
  if (!c.lastTwoTexts(&e.state, &e.reason)) return bad_length();
  const std::string what = "device event at step " + std::to_string(e.step);
  if (e.step >= kStepIndexEnd) return what + ": step index beyond 2^63 - 1";
  if (e.pen > 1) return what + ": pen " + std::to_string(e.pen) + " (expected 0, the drill, or 1, the mirror)";
  if (e.state.empty() || e.state.size() > kMaxDeviceStateBytes || !isPrintableAscii(e.state))
    return what + ": state " + quoteToken(e.state) + " is not a short printable word";
  if (e.reason.size() > kMaxReasonBytes)
    return what + ": reason of " + std::to_string(e.reason.size()) + " bytes is longer than " +
           std::to_string(kMaxReasonBytes);
  if (!isPrintableAscii(e.reason)) return what + ": reason " + quoteToken(e.reason) + " is not printable ASCII";
  if (rec_.devices.size() >= limits_.max_device_events)
    return "more than " + std::to_string(limits_.max_device_events) + " device events, the limit for one session";
  if (!rec_.devices.empty() && e.step < rec_.devices.back().step)
    return what + " comes after one at step " + std::to_string(rec_.devices.back().step);
  rec_.devices.push_back(std::move(e));
  return std::nullopt;
}

// A schedule belongs to the step record just before it, and says what that step reached; a step
// that did all its work has none.
std::optional<std::string> SessionParser::readSchedule(std::span<const uint8_t> payload) {
  if (payload.size() != kScheduleBytes)
    return "schedule payload of " + std::to_string(payload.size()) + " bytes, expected " +
           std::to_string(kScheduleBytes);
  Cursor c(payload);
  const uint64_t step = c.next<uint64_t>();
  SessionSchedule s;
  for (size_t r = 0; r < kPenCount; ++r) s.clusters[r] = c.next<uint32_t>();
  s.cuts = c.next<uint32_t>();
  const std::string what = "schedule for step " + std::to_string(step);
  if (last_kind_ != kStepRecord || rec_.steps.back().step != step)
    return what + " does not follow step " + std::to_string(step) + "'s record (it follows " + lastRecord() + ")";
  if (s.isDefault())
    return what + " is the default (every field 0xffffffff): a step that did all its work has no schedule record";
  rec_.steps.back().schedule = s;
  return std::nullopt;
}

std::optional<std::string> SessionParser::readEnd(std::span<const uint8_t> payload) {
  const auto bad_length = [&] {
    return "end payload of " + std::to_string(payload.size()) + " bytes does not match its string lengths";
  };
  if (payload.size() < kEndFixedBytes) return bad_length();
  Cursor c(payload);
  SessionEnd e;
  e.steps = c.next<uint64_t>();
  if (!c.lastTwoTexts(&e.final_hash, &e.reason)) return bad_length();
  if (!isLowerHex(e.final_hash, kHashHexDigits))
    return "end: final hash " + quoteToken(e.final_hash) + " is not 16 lower-case hex digits";
  if (e.reason.size() > kMaxReasonBytes)
    return "end: reason of " + std::to_string(e.reason.size()) + " bytes is longer than " +
           std::to_string(kMaxReasonBytes);
  if (!isPrintableAscii(e.reason)) return "end: reason " + quoteToken(e.reason) + " is not printable ASCII";
  rec_.end = std::move(e);
  return std::nullopt;
}

}  // namespace

// ---- 5. reading -----------------------------------------------------------------------------

Result<SessionRecording> parseSession(std::span<const uint8_t> bytes, const std::string& where,
                                      const SessionReadLimits& limits) {
  return guardParse<SessionRecording>(
      where, bytes.size(), [&] { return SessionParser(bytes, where, limits).parse(); }, "the session");
}

Result<SessionRecording> readSessionFile(const std::string& path, const SessionReadLimits& limits) {
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, limits.max_bytes);
  if (!bytes) return bytes.error();
  return parseSession(*bytes, path, limits);
}

// ---- 6. SessionWriter -----------------------------------------------------------------------

SessionWriter::~SessionWriter() {
  if (!file_) return;
  if (error_.empty() && !buffer_.empty()) {
    const size_t n = std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    bytes_written_ += n;
  }
  std::fclose(file_);  // the ".part" file stays for a later look or recovery
}

Status SessionWriter::open(const std::string& path, const SessionInfo& info) {
  assert(file_ == nullptr && "open() on a writer that is already open");
  if (file_) return makeError(path, "a session is already being written to " + shownPath(part_path_));
  if (std::optional<std::string> p = checkInfoValues(info)) return makeError(path, "header: " + *p);
  if (!paramsValue(info.params_json).is_object())
    return makeError(path, "header: params: the parameter set is not a JSON object");
  if (!info.guide_json.empty() && !paramsValue(info.guide_json).is_object())
    return makeError(path, "header: guide: the guide is not a JSON object");
  path_ = path;
  part_path_ = path + ".part";
  bytes_written_ = 0;
  error_.clear();
  buffer_.clear();
  appendHeader(buffer_, info);
  file_ = std::fopen(part_path_.c_str(), "wb");
  if (!file_) {
    buffer_.clear();
    return makeError(part_path_, std::string("cannot create: ") + std::strerror(errno));
  }
  if (Status s = flush(); !s) {
    std::fclose(file_);
    file_ = nullptr;
    std::remove(part_path_.c_str());  // nothing in it is readable yet
    return s;
  }
  return Ok{};
}

void SessionWriter::addRecord(uint8_t kind, const std::vector<uint8_t>& payload) {
  assert(file_ != nullptr && "add() before open() or after finish()");
  // After a failed write the file ends in a partial record, which reads as a truncation; appending
  // more would turn it into corruption, so nothing more is kept.
  if (!error_.empty()) return;
  appendRecord(buffer_, kind, payload);
}

void SessionWriter::add(const SessionStep& step) {
  encodeStep(scratch_, step);
  addRecord(kStepRecord, scratch_);
  if (!step.schedule.isDefault()) {
    encodeSchedule(scratch_, step.step, step.schedule);
    addRecord(kScheduleRecord, scratch_);
  }
}

void SessionWriter::add(const SessionParams& params) {
  encodeParams(scratch_, params);
  addRecord(kParamsRecord, scratch_);
}

void SessionWriter::add(const SessionGap& gap) {
  encodeGap(scratch_, gap);
  addRecord(kGapRecord, scratch_);
}

void SessionWriter::add(const SessionDeviceEvent& event) {
  encodeDevice(scratch_, event);
  addRecord(kDeviceRecord, scratch_);
}

Status SessionWriter::flush() {
  if (!file_) return makeError(path_, "no session file is open");
  if (!error_.empty()) return makeError(part_path_, error_);
  if (!buffer_.empty()) {
    const size_t n = std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    bytes_written_ += n;
    const bool complete = n == buffer_.size();
    buffer_.clear();  // keeps its capacity
    if (!complete) {
      error_ = std::string("write failed: ") + std::strerror(errno);
      return makeError(part_path_, error_);
    }
  }
  if (std::fflush(file_) != 0) {
    error_ = std::string("write failed: ") + std::strerror(errno);
    return makeError(part_path_, error_);
  }
  return Ok{};
}

Status SessionWriter::sync() {
  if (Status s = flush(); !s) return s;
  if (::fsync(::fileno(file_)) != 0) {
    error_ = std::string("fsync failed: ") + std::strerror(errno);
    return makeError(part_path_, error_);
  }
  return Ok{};
}

Status SessionWriter::finish(const SessionEnd& end) {
  if (!file_) return makeError(path_, "no session file is open");
  encodeEnd(scratch_, end);
  addRecord(kEndRecord, scratch_);
  Status s = sync();
  if (std::fclose(file_) != 0 && s) s = makeError(part_path_, std::string("close failed: ") + std::strerror(errno));
  file_ = nullptr;
  if (!s) return s;  // the ".part" file keeps what was written
  if (std::rename(part_path_.c_str(), path_.c_str()) != 0)
    return makeError(path_, "cannot rename " + shownPath(part_path_) + " to it: " + std::strerror(errno));
  return Ok{};
}

// ---- 7. encodeSession -----------------------------------------------------------------------

std::vector<uint8_t> encodeSession(const SessionRecording& recording) {
  std::vector<uint8_t> out, payload;
  appendHeader(out, recording.info);
  const std::vector<SessionParams>& params = recording.params;
  const std::vector<SessionGap>& gaps = recording.gaps;
  size_t next_params = 0, next_gap = 0;
  // Emits, in order, the parameter sets in force by step `before` (from_step <= before) and the gaps
  // that start before it (first_step < before). Where both are due, the one that starts earlier comes
  // first, and a parameter set before a gap that starts at its from_step (so the reader sees
  // from_step where it expects the gap's first step).
  const auto emitDue = [&](uint64_t before, bool all) {
    for (;;) {
      const bool params_due = next_params < params.size() && (all || params[next_params].from_step <= before);
      const bool gap_due = next_gap < gaps.size() && (all || gaps[next_gap].first_step < before);
      if (params_due && (!gap_due || params[next_params].from_step <= gaps[next_gap].first_step)) {
        encodeParams(payload, params[next_params++]);
        appendRecord(out, kParamsRecord, payload);
      } else if (gap_due) {
        encodeGap(payload, gaps[next_gap++]);
        appendRecord(out, kGapRecord, payload);
      } else {
        return;
      }
    }
  };
  // Device events go just before the first step they came before (and after that step's
  // parameter set), the rest at the end.
  size_t next_device = 0;
  const auto emitDevices = [&](uint64_t before, bool all) {
    while (next_device < recording.devices.size() && (all || recording.devices[next_device].step <= before)) {
      encodeDevice(payload, recording.devices[next_device++]);
      appendRecord(out, kDeviceRecord, payload);
    }
  };
  for (const SessionStep& s : recording.steps) {
    emitDue(s.step, false);
    emitDevices(s.step, false);
    encodeStep(payload, s);
    appendRecord(out, kStepRecord, payload);
    if (!s.schedule.isDefault()) {
      encodeSchedule(payload, s.step, s.schedule);
      appendRecord(out, kScheduleRecord, payload);
    }
  }
  emitDue(0, true);
  emitDevices(0, true);
  if (recording.end) {
    encodeEnd(payload, *recording.end);
    appendRecord(out, kEndRecord, payload);
  }
  return out;
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace dentsim
