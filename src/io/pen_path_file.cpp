// Pen path reading and writing: a strict CSV reader, a streaming JSON reader, shared sample checks, exact writers.
//
// Contents
//   1. Small helpers: quoting, number text, number parsing
//   2. Sample checks (shared by both readers and savePenPath)
//   3. CSV reader
//   4. JSON reader (nlohmann SAX events into a fixed state machine, never a DOM)
//   5. Loading, with format detection
//   6. Writers
#include "io/pen_path_file.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <new>
#include <optional>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/file_kind.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

// ---- 1. helpers -----------------------------------------------------------------------------

constexpr size_t kPenCount = 2;                // PenRole values
constexpr uint64_t kMaxButtons = 0xffffffffu;  // buttons are 32 bits

// The CSV columns, in the order of kPenPathCsvHeader; all but pen and buttons are doubles.
constexpr const char* kCsvColumnNames[] = {"t_s", "pen",  "x_mm", "y_mm",    "z_mm", "qw",
                                           "qx",  "qy",   "qz",   "buttons", "pedal"};
constexpr size_t kCsvColumns = std::size(kCsvColumnNames);
constexpr size_t kCsvPenColumn = 1;
constexpr size_t kCsvButtonsColumn = 9;
static_assert(size_t(std::count(kPenPathCsvHeader.begin(), kPenPathCsvHeader.end(), ',')) + 1 == kCsvColumns);

std::string quote(std::string_view token, size_t max_shown = 32) { return quoteToken(token, max_shown); }

// The shortest text that reads back to the same double ("0.1", "1e-300", "-0", "inf", "nan").
std::string numberText(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  assert(ec == std::errc());
  return std::string(buf, end);
}

void appendNumber(std::string& out, double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  assert(ec == std::errc());
  out.append(buf, end);
}

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view trimBlanks(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

enum class NumberParse { Ok, NotANumber, OutOfRange };

// One double in C syntax, whole token only. Accepts a leading '+', which from_chars does not; "nan"
// and "inf" parse, and the sample checks refuse them. Values beyond the double range, including
// ones too small to be anything but zero, are refused rather than rounded.
NumberParse parseDouble(std::string_view token, double* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  if (token.empty()) return NumberParse::NotANumber;
  const char* end = token.data() + token.size();
  double d = 0.0;
  const auto [ptr, ec] = std::from_chars(token.data(), end, d);
  if (ptr != end) return NumberParse::NotANumber;
  if (ec == std::errc::result_out_of_range) return NumberParse::OutOfRange;
  if (ec != std::errc()) return NumberParse::NotANumber;
  *value = d;
  return NumberParse::Ok;
}

std::optional<PenRole> penFromName(std::string_view name) {
  if (name == "drill") return PenRole::Drill;
  if (name == "mirror") return PenRole::Mirror;
  return std::nullopt;
}

// ---- 2. sample checks -----------------------------------------------------------------------

// Which value a problem is about; each encoding names it its own way.
enum class Field : uint8_t { TimeS, Pen, Position, Rotation, Buttons, Pedal };

struct Problem {
  Field field = Field::TimeS;
  int component = -1;  // 0..2 of the position, 0..3 (w, x, y, z) of the rotation; -1 for the whole value
  std::string what;
};

// The checks that do not depend on the encoding, applied sample by sample in file order.
class SampleChecker {
 public:
  // Checks `s`; when it passes, remembers its time for its pen's order and, with `normalise`, makes
  // its rotation unit. The first problem found is returned.
  std::optional<Problem> check(PenSample& s, bool normalise) {
    if (!std::isfinite(s.t_s)) return Problem{Field::TimeS, -1, "not finite (" + numberText(s.t_s) + ")"};
    if (s.t_s < 0) return Problem{Field::TimeS, -1, "negative time " + numberText(s.t_s) + " s"};
    const auto pen = size_t(s.pen);
    if (pen >= kPenCount) return Problem{Field::Pen, -1, "unknown pen role " + std::to_string(pen)};
    if (s.t_s < last_t_s_[pen])
      return Problem{Field::TimeS, -1,
                     "time " + numberText(s.t_s) + " s is earlier than the previous " +
                         std::string(penRoleName(s.pen)) + " sample's " + numberText(last_t_s_[pen]) + " s"};
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(s.pose.position[a]))
        return Problem{Field::Position, a, "not finite (" + numberText(s.pose.position[a]) + ")"};
    Quat& q = s.pose.rotation;
    const double q_parts[4] = {q.w, q.x, q.y, q.z};
    for (int a = 0; a < 4; ++a)
      if (!std::isfinite(q_parts[a])) return Problem{Field::Rotation, a, "not finite (" + numberText(q_parts[a]) + ")"};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(std::fabs(n - 1.0) <= kPenRotationNormTolerance))
      return Problem{Field::Rotation, -1,
                     "norm " + numberText(n) + " is not within " + numberText(kPenRotationNormTolerance) +
                         " of 1 (not a unit quaternion)"};
    if (!std::isfinite(s.pedal)) return Problem{Field::Pedal, -1, "not finite (" + numberText(s.pedal) + ")"};
    if (!(s.pedal >= 0.0 && s.pedal <= 1.0))
      return Problem{Field::Pedal, -1, numberText(s.pedal) + " is outside [0, 1]"};

    // A rotation that is unit to rounding stays as it is, so that normalising is idempotent and a
    // path read, written and read again keeps every bit.
    constexpr double kUnitSlack = 8 * std::numeric_limits<double>::epsilon();
    if (normalise && std::fabs(n - 1.0) > kUnitSlack) q = Quat{q.w / n, q.x / n, q.y / n, q.z / n};
    last_t_s_[pen] = s.t_s;
    return std::nullopt;
  }

 private:
  double last_t_s_[kPenCount] = {0.0, 0.0};  // time of each pen's last sample [s]
};

// JSON names: "t_s", "position_mm[1]", "rotation_wxyz".
std::string jsonFieldName(const Problem& p) {
  const auto indexed = [&](const char* name) {
    return p.component < 0 ? std::string(name) : std::string(name) + "[" + std::to_string(p.component) + "]";
  };
  switch (p.field) {
    case Field::TimeS: return "t_s";
    case Field::Pen: return "pen";
    case Field::Position: return indexed("position_mm");
    case Field::Rotation: return indexed("rotation_wxyz");
    case Field::Buttons: return "buttons";
    case Field::Pedal: return "pedal";
  }
  return "?";
}

// CSV names are the header's columns ("x_mm", "qw"); the rotation as a whole is "rotation".
std::string csvFieldName(const Problem& p) {
  constexpr size_t kFirstPosition = 2, kFirstRotation = 5;  // columns of x_mm and qw
  switch (p.field) {
    case Field::TimeS: return "t_s";
    case Field::Pen: return "pen";
    case Field::Position: return p.component < 0 ? "position" : kCsvColumnNames[kFirstPosition + size_t(p.component)];
    case Field::Rotation: return p.component < 0 ? "rotation" : kCsvColumnNames[kFirstRotation + size_t(p.component)];
    case Field::Buttons: return "buttons";
    case Field::Pedal: return "pedal";
  }
  return "?";
}

std::string sampleLabel(size_t index) { return "samples[" + std::to_string(index) + "]"; }

std::string tooManySamples(uint64_t limit) {
  return "more than " + std::to_string(limit) + " samples, the limit for one path";
}

// The readers accept samples of different pens in any order of time; the path is sorted by time,
// keeping each pen's order (already non-decreasing).
void sortByTime(PenPath& path) {
  const auto earlier = [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; };
  if (!std::is_sorted(path.samples.begin(), path.samples.end(), earlier))
    std::stable_sort(path.samples.begin(), path.samples.end(), earlier);
}


// ---- 3. CSV reader --------------------------------------------------------------------------

class CsvReader {
 public:
  CsvReader(const std::string& where, const PenPathReadLimits& limits) : where_(where), limits_(limits) {}

  Result<PenPath> read(std::string_view text) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte order mark
    PenPath path;
    bool have_header = false;
    size_t pos = 0;
    while (pos < text.size()) {
      ++line_;
      const size_t newline = text.find('\n', pos);
      std::string_view line = text.substr(pos, newline == std::string_view::npos ? text.npos : newline - pos);
      pos = newline == std::string_view::npos ? text.size() : newline + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

      const std::string_view trimmed = trimBlanks(line);
      if (!trimmed.empty() && trimmed.front() == '#' && !have_header) {
        // "# frame: NAME" before the header says which frame the poses are in.
        std::string_view rest = trimBlanks(trimmed.substr(1));
        if (rest.substr(0, 6) == "frame:") {
          rest = trimBlanks(rest.substr(6));
          if (rest == "tooth") path.frame = PenFrame::Tooth;
          else if (rest == "simulation") path.frame = PenFrame::Simulation;
          else return fail("unknown frame " + quote(rest, 40) + " (tooth or simulation)");
        }
        continue;
      }
      if (trimmed.empty() || trimmed.front() == '#') continue;
      if (!have_header) {
        if (line != kPenPathCsvHeader)
          return fail("expected the header " + quote(kPenPathCsvHeader, 80) + ", found " + quote(line, 80));
        have_header = true;
        continue;
      }
      if (path.samples.size() >= limits_.max_samples) return fail(tooManySamples(limits_.max_samples));
      Result<PenSample> sample = parseRow(line);
      if (!sample) return sample.error();
      path.samples.push_back(*sample);
    }
    if (!have_header) return makeError(where_, "no samples (no header line)");
    if (path.samples.empty()) return makeError(where_, "no samples");
    sortByTime(path);
    return path;
  }

 private:
  Result<PenSample> parseRow(std::string_view line) {
    std::array<std::string_view, kCsvColumns> cols;
    const size_t count = size_t(std::count(line.begin(), line.end(), ',')) + 1;
    if (count != kCsvColumns)
      return fail("expected " + std::to_string(kCsvColumns) + " comma-separated columns, found " +
                  std::to_string(count));
    for (size_t c = 0; c < kCsvColumns; ++c) {
      const size_t comma = line.find(',');
      cols[c] = trimBlanks(line.substr(0, comma));
      line = comma == std::string_view::npos ? std::string_view() : line.substr(comma + 1);
    }

    PenSample s;
    double* const numbers[kCsvColumns] = {&s.t_s, nullptr, &s.pose.position.x, &s.pose.position.y,
                                          &s.pose.position.z, &s.pose.rotation.w, &s.pose.rotation.x,
                                          &s.pose.rotation.y, &s.pose.rotation.z, nullptr, &s.pedal};
    for (size_t c = 0; c < kCsvColumns; ++c) {
      const std::string_view tok = cols[c];
      const std::string name = kCsvColumnNames[c];
      if (c == kCsvPenColumn) {
        const std::optional<PenRole> pen = penFromName(tok);
        if (!pen) return fail(name + ": expected \"drill\" or \"mirror\", found " + quote(tok));
        s.pen = *pen;
      } else if (c == kCsvButtonsColumn) {
        // Digits only: no sign, no fraction, no hex.
        uint64_t v = 0;
        const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (tok.empty() || ptr != tok.data() + tok.size() || ec != std::errc() || v > kMaxButtons)
          return fail(name + ": expected an integer in [0, " + std::to_string(kMaxButtons) + "], found " + quote(tok));
        s.buttons = uint32_t(v);
      } else {
        switch (parseDouble(tok, numbers[c])) {
          case NumberParse::Ok: break;
          case NumberParse::NotANumber: return fail(name + ": expected a number, found " + quote(tok));
          case NumberParse::OutOfRange: return fail(name + ": number " + quote(tok) + " is out of the double range");
        }
      }
    }
    if (std::optional<Problem> p = checker_.check(s, true)) return fail(csvFieldName(*p) + ": " + p->what);
    return s;
  }

  Error fail(const std::string& what) const {
    const std::string at = std::to_string(line_);
    return Error{(where_.empty() ? "line " + at : where_ + ":" + at) + ": " + what};
  }

  const std::string& where_;
  const PenPathReadLimits& limits_;
  SampleChecker checker_;
  uint64_t line_ = 0;  // current line, from 1
};

// ---- 4. JSON reader -------------------------------------------------------------------------

// What a JSON value is, for the state machine and for "found ..." in messages.
struct JsonValue {
  enum class Kind { Null, Boolean, Number, String, Object, Array } kind = Kind::Null;
  double number = 0;               // Number: its value (integers converted)
  bool integer = false;            // Number: written without fraction or exponent
  bool negative = false;           // Number, integer: below zero
  uint64_t magnitude = 0;          // Number, integer, not negative: its value
  std::string_view text;           // Number: as written; String: its text

  static JsonValue of(Kind k) {
    JsonValue v;
    v.kind = k;
    return v;
  }
  static JsonValue wholeNumber(bool negative, uint64_t magnitude, double number, std::string_view text) {
    JsonValue v = of(Kind::Number);
    v.number = number;
    v.integer = true;
    v.negative = negative;
    v.magnitude = magnitude;
    v.text = text;
    return v;
  }
  static JsonValue realNumber(double number, std::string_view text) {
    JsonValue v = of(Kind::Number);
    v.number = number;
    v.text = text;
    return v;
  }
  static JsonValue stringValue(std::string_view text) {
    JsonValue v = of(Kind::String);
    v.text = text;
    return v;
  }

  std::string describe() const {
    switch (kind) {
      case Kind::Null: return "null";
      case Kind::Boolean: return "a boolean";
      case Kind::Number: return "the number " + quote(text);
      case Kind::String: return "the string " + quote(text);
      case Kind::Object: return "an object";
      case Kind::Array: return "an array";
    }
    return "?";
  }
};

// The fields of one sample, in the order messages report them missing.
enum SampleKey : uint8_t { kTime, kPen, kPosition, kRotation, kButtons, kPedal, kSampleKeyCount };
constexpr const char* kSampleKeys[kSampleKeyCount] = {"t_s", "pen", "position_mm", "rotation_wxyz", "buttons", "pedal"};
enum RootKey : uint8_t { kFormat, kVersion, kSamples, kFrame, kRootKeyCount };
constexpr const char* kRootKeys[kRootKeyCount] = {"format", "version", "samples", "frame"};
constexpr bool kRootKeyRequired[kRootKeyCount] = {true, true, true, false};

// Receives nlohmann's SAX events. The grammar is fixed, so the reader is a small state machine that
// refuses anything unexpected at once: memory stays bounded by the samples themselves, and nesting
// never goes deeper than a sample's vectors.
class JsonReader {
 public:
  JsonReader(const std::string& where, const PenPathReadLimits& limits) : where_(where), limits_(limits) {}

  Result<PenPath> read(std::string_view text) {
    const bool done = nlohmann::json::sax_parse(text.begin(), text.end(), this);
    if (!done || state_ != State::End) return error_ ? *error_ : makeError(where_, "not a complete pen path");
    sortByTime(path_);
    return std::move(path_);
  }

  // -- SAX interface (the names and signatures are nlohmann's) --
  bool null() { return value(JsonValue::of(JsonValue::Kind::Null)); }
  bool boolean(bool) { return value(JsonValue::of(JsonValue::Kind::Boolean)); }
  bool number_integer(int64_t v) {
    const std::string text = std::to_string(v);
    return value(JsonValue::wholeNumber(v < 0, v < 0 ? 0 : uint64_t(v), double(v), text));
  }
  bool number_unsigned(uint64_t v) {
    const std::string text = std::to_string(v);
    return value(JsonValue::wholeNumber(false, v, double(v), text));
  }
  bool number_float(double v, const std::string& text) { return value(JsonValue::realNumber(v, text)); }
  bool string(std::string& s) { return value(JsonValue::stringValue(s)); }
  bool binary(nlohmann::json::binary_t&) { return fail("", "unexpected binary value"); }
  bool start_object(size_t) { return value(JsonValue::of(JsonValue::Kind::Object)); }
  bool start_array(size_t) { return value(JsonValue::of(JsonValue::Kind::Array)); }
  bool key(std::string& k);
  bool end_object();
  bool end_array();
  bool parse_error(size_t, const std::string&, const nlohmann::json::exception& ex);

 private:
  enum class State {
    Start,        // before the root object
    RootKey,      // in the root object, before a key or its end
    RootValue,    // after a root key
    SampleList,   // in "samples", before a sample or the end
    SampleKey,    // in a sample, before a key or its end
    SampleValue,  // after a sample key
    Vector,       // in a sample's position or rotation array
    End,          // after the root object
  };

  bool value(const JsonValue& v);
  bool rootValue(const JsonValue& v);
  bool sampleValue(const JsonValue& v);
  bool finishSample();
  double* vectorPart(size_t i);

  // "<where>: <context>: <what>", or "<where>: <what>" when there is no context.
  bool fail(const std::string& context, const std::string& what) {
    error_ = makeError(where_, context.empty() ? what : context + ": " + what);
    return false;
  }
  std::string sampleField(uint8_t key) const { return sampleLabel(path_.samples.size()) + "." + kSampleKeys[key]; }

  const std::string& where_;
  const PenPathReadLimits& limits_;
  std::optional<Error> error_;
  State state_ = State::Start;
  PenPath path_;
  SampleChecker checker_;

  bool root_seen_[kRootKeyCount] = {};
  uint8_t root_key_ = 0;
  bool sample_seen_[kSampleKeyCount] = {};
  uint8_t sample_key_ = 0;
  PenSample sample_;
  size_t vector_count_ = 0;  // numbers read into the current position or rotation
};

bool JsonReader::value(const JsonValue& v) {
  using Kind = JsonValue::Kind;
  switch (state_) {
    case State::Start:
      if (v.kind != Kind::Object) return fail("", "expected a JSON object (a pen path), found " + v.describe());
      state_ = State::RootKey;
      return true;
    case State::RootValue: return rootValue(v);
    case State::SampleList:
      if (v.kind != Kind::Object)
        return fail(sampleLabel(path_.samples.size()), "expected an object, found " + v.describe());
      if (path_.samples.size() >= limits_.max_samples) return fail("samples", tooManySamples(limits_.max_samples));
      sample_ = PenSample{};
      std::fill(std::begin(sample_seen_), std::end(sample_seen_), false);
      state_ = State::SampleKey;
      return true;
    case State::SampleValue: return sampleValue(v);
    case State::Vector: {
      const size_t n = sample_key_ == kPosition ? 3 : 4;
      if (v.kind != Kind::Number)
        return fail(sampleField(sample_key_) + "[" + std::to_string(vector_count_) + "]",
                    "expected a number, found " + v.describe());
      if (vector_count_ == n)
        return fail(sampleField(sample_key_), "expected " + std::to_string(n) + " numbers, found more");
      *vectorPart(vector_count_++) = v.number;
      return true;
    }
    case State::RootKey:
    case State::SampleKey:
    case State::End: break;  // nlohmann delivers keys, ends or a syntax error here
  }
  return fail("", "unexpected " + v.describe());
}

bool JsonReader::rootValue(const JsonValue& v) {
  using Kind = JsonValue::Kind;
  const std::string name = kRootKeys[root_key_];
  switch (root_key_) {
    case kFormat:
      if (v.kind != Kind::String || v.text != kPenPathJsonFormat)
        return fail(name, "expected " + quote(kPenPathJsonFormat) + ", found " + v.describe());
      state_ = State::RootKey;
      return true;
    case kVersion:
      if (v.kind != Kind::Number) return fail(name, "expected a number, found " + v.describe());
      if (!v.integer || v.negative || v.magnitude != uint64_t(kPenPathJsonVersion))
        return fail(name, "unsupported version " + quote(v.text) + " (this reader knows version " +
                              std::to_string(kPenPathJsonVersion) + ")");
      state_ = State::RootKey;
      return true;
    case kFrame:
      if (v.kind != Kind::String || (v.text != "tooth" && v.text != "simulation"))
        return fail(name, "expected \"tooth\" or \"simulation\", found " + v.describe());
      path_.frame = v.text == "tooth" ? PenFrame::Tooth : PenFrame::Simulation;
      state_ = State::RootKey;
      return true;
    default:
      if (v.kind != Kind::Array) return fail(name, "expected an array of samples, found " + v.describe());
      state_ = State::SampleList;
      return true;
  }
}

bool JsonReader::sampleValue(const JsonValue& v) {
  using Kind = JsonValue::Kind;
  const auto name = [&] { return sampleField(sample_key_); };  // built only for a message
  switch (sample_key_) {
    case kTime:
    case kPedal:
      if (v.kind != Kind::Number) return fail(name(), "expected a number, found " + v.describe());
      (sample_key_ == kTime ? sample_.t_s : sample_.pedal) = v.number;
      break;
    case kPen: {
      const std::optional<PenRole> pen = v.kind == Kind::String ? penFromName(v.text) : std::nullopt;
      if (!pen) return fail(name(), "expected \"drill\" or \"mirror\", found " + v.describe());
      sample_.pen = *pen;
      break;
    }
    case kButtons:
      if (v.kind != Kind::Number || !v.integer || v.negative || v.magnitude > kMaxButtons)
        return fail(name(), "expected an integer in [0, " + std::to_string(kMaxButtons) + "], found " + v.describe());
      sample_.buttons = uint32_t(v.magnitude);
      break;
    default:  // position_mm, rotation_wxyz
      if (v.kind != Kind::Array)
        return fail(name(), "expected an array of " + std::string(sample_key_ == kPosition ? "3" : "4") +
                              " numbers, found " + v.describe());
      vector_count_ = 0;
      state_ = State::Vector;
      return true;
  }
  state_ = State::SampleKey;
  return true;
}

double* JsonReader::vectorPart(size_t i) {
  if (sample_key_ == kPosition) return &sample_.pose.position[int(i)];
  Quat& q = sample_.pose.rotation;
  double* const parts[] = {&q.w, &q.x, &q.y, &q.z};
  return parts[i];
}

bool JsonReader::key(std::string& k) {
  if (state_ == State::RootKey) {
    const auto* it = std::find(std::begin(kRootKeys), std::end(kRootKeys), std::string_view(k));
    if (it == std::end(kRootKeys)) return fail("", "unknown key " + quote(k));
    root_key_ = uint8_t(it - std::begin(kRootKeys));
    if (root_seen_[root_key_]) return fail(kRootKeys[root_key_], "duplicate key");
    root_seen_[root_key_] = true;
    state_ = State::RootValue;
    return true;
  }
  assert(state_ == State::SampleKey);
  const auto* it = std::find(std::begin(kSampleKeys), std::end(kSampleKeys), std::string_view(k));
  if (it == std::end(kSampleKeys)) return fail(sampleLabel(path_.samples.size()), "unknown key " + quote(k));
  sample_key_ = uint8_t(it - std::begin(kSampleKeys));
  if (sample_seen_[sample_key_]) return fail(sampleField(sample_key_), "duplicate key");
  sample_seen_[sample_key_] = true;
  state_ = State::SampleValue;
  return true;
}

bool JsonReader::finishSample() {
  for (uint8_t k = 0; k < kSampleKeyCount; ++k)
    if (!sample_seen_[k]) return fail(sampleField(k), "missing");
  if (std::optional<Problem> p = checker_.check(sample_, true))
    return fail(sampleLabel(path_.samples.size()) + "." + jsonFieldName(*p), p->what);
  path_.samples.push_back(sample_);
  state_ = State::SampleList;
  return true;
}

bool JsonReader::end_object() {
  if (state_ == State::SampleKey) return finishSample();
  assert(state_ == State::RootKey);
  for (uint8_t k = 0; k < kRootKeyCount; ++k)
    if (kRootKeyRequired[k] && !root_seen_[k]) return fail("", "missing key " + quote(kRootKeys[k]));
  if (path_.samples.empty()) return fail("", "no samples");
  state_ = State::End;
  return true;
}

bool JsonReader::end_array() {
  if (state_ == State::SampleList) {
    state_ = State::RootKey;
    return true;
  }
  assert(state_ == State::Vector);
  const size_t n = sample_key_ == kPosition ? 3 : 4;
  if (vector_count_ != n)
    return fail(sampleField(sample_key_),
                "expected " + std::to_string(n) + " numbers, found " + std::to_string(vector_count_));
  state_ = State::SampleKey;
  return true;
}

bool JsonReader::parse_error(size_t position, const std::string&, const nlohmann::json::exception& ex) {
  // what() reads "[json.exception.parse_error.101] parse error at line 2, column 5: ..."; the tag
  // means nothing to a user.
  std::string_view what = ex.what();
  if (const size_t tag_end = what.find("] "); !what.empty() && what.front() == '[' && tag_end != what.npos)
    what.remove_prefix(tag_end + 2);
  std::string clean = quote(what, 240);
  clean = clean.substr(1, clean.size() - 2);  // without the quotes
  // nlohmann reports a number beyond the double range (out_of_range.406) here too, without a place.
  constexpr int kNumberOverflow = 406;
  if (ex.id == kNumberOverflow)
    return fail("", clean + " (beyond the double range) near byte " + std::to_string(position));
  return fail("", "not valid JSON: " + clean);
}

// ---- 5. loading -----------------------------------------------------------------------------

bool endsWithNoCase(const std::string& s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  for (size_t i = 0; i < suffix.size(); ++i) {
    char c = s[s.size() - suffix.size() + i];
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if (c != suffix[i]) return false;
  }
  return true;
}

// JSON when the name says so, or when the name says nothing and the text opens with '{'.
bool looksLikeJson(const std::string& path, std::string_view text) {
  if (endsWithNoCase(path, ".json")) return true;
  if (endsWithNoCase(path, ".csv")) return false;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const size_t first = text.find_first_not_of(" \t\r\n");
  return first != std::string_view::npos && text[first] == '{';
}

}  // namespace

Result<PenPath> parsePenPathCsv(std::string_view text, const std::string& where, const PenPathReadLimits& limits) {
  return guardParse<PenPath>(where, text.size(), [&] { return CsvReader(where, limits).read(text); }, "the pen path");
}

Result<PenPath> parsePenPathJson(std::string_view text, const std::string& where, const PenPathReadLimits& limits) {
  return guardParse<PenPath>(where, text.size(), [&] { return JsonReader(where, limits).read(text); }, "the pen path");
}

Result<PenPath> loadPenPath(const std::string& path, const PenPathReadLimits& limits) {
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, kMaxPenPathFileBytes);
  if (!bytes) return bytes.error();
  // A pen path is text, so any format known by its magic bytes is the wrong file.
  if (auto other = refuseOtherKind(*bytes, FileKind::Unknown, path, "a pen path (CSV or JSON)")) return *other;
  const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
  return looksLikeJson(path, text) ? parsePenPathJson(text, path, limits) : parsePenPathCsv(text, path, limits);
}

std::string_view penRoleName(PenRole pen) {
  switch (pen) {
    case PenRole::Drill: return "drill";
    case PenRole::Mirror: return "mirror";
  }
  return "unknown";
}

bool hasPen(const PenPath& path, PenRole pen) {
  return std::any_of(path.samples.begin(), path.samples.end(), [pen](const PenSample& s) { return s.pen == pen; });
}

Status checkPenPath(const PenPath& path, const std::string& where) {
  if (path.samples.empty()) return makeError(where, "no samples");
  SampleChecker checker;
  for (size_t i = 0; i < path.samples.size(); ++i) {
    PenSample s = path.samples[i];
    if (std::optional<Problem> p = checker.check(s, false))
      return makeError(where, sampleLabel(i) + "." + jsonFieldName(*p) + ": " + p->what);
    if (i > 0 && s.t_s < path.samples[i - 1].t_s)
      return makeError(where, sampleLabel(i) + ".t_s: time " + numberText(s.t_s) + " s is earlier than " +
                                  sampleLabel(i - 1) + "'s " + numberText(path.samples[i - 1].t_s) +
                                  " s (samples must be sorted by time)");
  }
  return Ok{};
}

// ---- 6. writers -----------------------------------------------------------------------------

namespace {

// A JSON number that reads back as the same double: never an integer token ("-0" would read as the
// integer 0 and lose its sign), and null for what JSON cannot hold.
void appendJsonNumber(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  const size_t start = out.size();
  appendNumber(out, v);
  if (out.find_first_of(".e", start) == std::string::npos) out += ".0";
}

// [a,b,...] with each number as appendJsonNumber writes it.
void appendJsonArray(std::string& out, std::initializer_list<double> values) {
  out += '[';
  for (const double* v = values.begin(); v != values.end(); ++v) {
    if (v != values.begin()) out += ',';
    appendJsonNumber(out, *v);
  }
  out += ']';
}

constexpr size_t kCsvBytesPerSample = 160;   // a row of shortest doubles, generous [B]
constexpr size_t kJsonBytesPerSample = 260;  // a sample object, generous [B]

}  // namespace

std::string penPathCsv(const PenPath& path) {
  std::string out;
  out.reserve(kPenPathCsvHeader.size() + 1 + path.samples.size() * kCsvBytesPerSample);
  if (path.frame == PenFrame::Tooth) {
    out += kPenPathCsvToothFrame;
    out += '\n';
  }
  out += kPenPathCsvHeader;
  out += '\n';
  for (const PenSample& s : path.samples) {
    const Vec3& p = s.pose.position;
    const Quat& q = s.pose.rotation;
    appendNumber(out, s.t_s);
    out += ',';
    out += penRoleName(s.pen);
    for (double v : {p.x, p.y, p.z, q.w, q.x, q.y, q.z}) {
      out += ',';
      appendNumber(out, v);
    }
    out += ',';
    out += std::to_string(s.buttons);
    out += ',';
    appendNumber(out, s.pedal);
    out += '\n';
  }
  return out;
}

std::string penPathJson(const PenPath& path) {
  std::string out;
  out.reserve(128 + path.samples.size() * kJsonBytesPerSample);
  out += "{\"format\":\"";
  out += kPenPathJsonFormat;
  out += "\",\"version\":" + std::to_string(kPenPathJsonVersion) + ",";
  if (path.frame == PenFrame::Tooth) out += "\"frame\":\"tooth\",";
  out += "\"samples\":[";
  for (size_t i = 0; i < path.samples.size(); ++i) {
    const PenSample& s = path.samples[i];
    const Vec3& p = s.pose.position;
    const Quat& q = s.pose.rotation;
    out += i == 0 ? "\n" : ",\n";
    out += "{\"t_s\":";
    appendJsonNumber(out, s.t_s);
    out += ",\"pen\":\"";
    out += penRoleName(s.pen);
    out += "\",\"position_mm\":";
    appendJsonArray(out, {p.x, p.y, p.z});
    out += ",\"rotation_wxyz\":";
    appendJsonArray(out, {q.w, q.x, q.y, q.z});
    out += ",\"buttons\":" + std::to_string(s.buttons) + ",\"pedal\":";
    appendJsonNumber(out, s.pedal);
    out += '}';
  }
  out += "\n]}\n";
  return out;
}

Status savePenPath(const std::string& file, const PenPath& path) {
  if (Status s = checkPenPath(path, file); !s) return s;
  try {
    const std::string text = endsWithNoCase(file, ".json") ? penPathJson(path) : penPathCsv(path);
    return writeFileAtomic(file, text);
  } catch (const std::bad_alloc&) {
    return makeError(file, "out of memory encoding " + std::to_string(path.samples.size()) + " samples");
  }
}

}  // namespace dentsim
