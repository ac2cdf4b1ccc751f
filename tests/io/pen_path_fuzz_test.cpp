// Bounded, deterministic mutation fuzzing of the pen path readers: hostile text never crashes them, accepted paths are valid, and every failure is one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "io/pen_path_file.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

using test::pick;

const std::string kCsvWhere = "fuzz.csv";
const std::string kJsonWhere = "fuzz.json";

// Tight, so that a duplicated run of samples could not make a case allocate much.
PenPathReadLimits fuzzLimits() {
  PenPathReadLimits limits;
  limits.max_samples = 64;
  return limits;
}

// Six samples of both pens, with equal times, a tilted rotation, buttons and the pedal in use.
PenPath seedPath() {
  const Quat tilted = Quat::fromAxisAngle({1, 2, 3}, 0.7);
  const auto s = [](double t, PenRole pen, Vec3 p, Quat q, uint32_t buttons, double pedal) {
    PenSample out;
    out.t_s = t;
    out.pen = pen;
    out.pose = {p, q};
    out.buttons = buttons;
    out.pedal = pedal;
    return out;
  };
  PenPath path;
  path.samples = {s(0, PenRole::Drill, {10, 20, 30}, {}, 0, 0),
                  s(0, PenRole::Mirror, {-5, 0, 12}, tilted, 0, 0),
                  s(0.001, PenRole::Drill, {10, 20, 29.9}, tilted, 1, 0.25),
                  s(0.002, PenRole::Drill, {10.1, 20, 29.8}, tilted.conjugate(), 3, 1),
                  s(0.002, PenRole::Mirror, {-5, 0.5, 12}, {}, 0, 0),
                  s(1.5, PenRole::Mirror, {-5, 1, 12}, tilted, 4294967295u, 0.1)};
  return path;
}

// Accepted paths must be usable as they are, and write and read back unchanged; rejections must be
// one line naming the source ("fuzz.csv:<line>: ..." or "fuzz.csv: ..." for CSV).
void checkOutcome(const Result<PenPath>& r, const std::string& where, int iteration, int* accepted, int* rejected) {
  if (!r.ok()) {
    ++*rejected;
    const std::string& m = r.message();
    if (where == kCsvWhere && m.rfind(where + ":", 0) == 0 && m.size() > where.size() + 1 &&
        std::isdigit(uint8_t(m[where.size() + 1]))) {
      // "fuzz.csv:12: ..." is the same check with the line number in the way.
      const size_t colon = m.find(": ", where.size() + 1);
      ASSERT_NE(colon, std::string::npos) << m;
      test::assertOneLineRejection(where + m.substr(colon), where, iteration);
    } else {
      test::assertOneLineRejection(m, where, iteration);
    }
    return;
  }
  ++*accepted;
  const std::vector<PenSample>& samples = r->samples;
  ASSERT_FALSE(samples.empty()) << "iteration " << iteration;
  ASSERT_LE(samples.size(), fuzzLimits().max_samples) << "iteration " << iteration;
  double last[2] = {0, 0};
  for (size_t i = 0; i < samples.size(); ++i) {
    const PenSample& s = samples[i];
    ASSERT_TRUE(s.pen == PenRole::Drill || s.pen == PenRole::Mirror) << "iteration " << iteration;
    ASSERT_TRUE(std::isfinite(s.t_s) && s.t_s >= 0) << "iteration " << iteration;
    if (i > 0) {
      ASSERT_GE(s.t_s, samples[i - 1].t_s) << "iteration " << iteration;
    }
    ASSERT_GE(s.t_s, last[size_t(s.pen)]) << "iteration " << iteration;
    last[size_t(s.pen)] = s.t_s;
    ASSERT_TRUE(finite(s.pose.position)) << "iteration " << iteration;
    const Quat& q = s.pose.rotation;
    ASSERT_TRUE(q.finite()) << "iteration " << iteration;
    ASSERT_NEAR(std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z), 1.0, 1e-12) << "iteration " << iteration;
    ASSERT_TRUE(s.pedal >= 0 && s.pedal <= 1) << "iteration " << iteration;
  }
  ASSERT_TRUE(checkPenPath(*r, where).ok()) << "iteration " << iteration;
  const Result<PenPath> csv = parsePenPathCsv(penPathCsv(*r), kCsvWhere, fuzzLimits());
  ASSERT_TRUE(csv.ok()) << csv.message();
  ASSERT_EQ(*csv, *r) << "iteration " << iteration;
  const Result<PenPath> json = parsePenPathJson(penPathJson(*r), kJsonWhere, fuzzLimits());
  ASSERT_TRUE(json.ok()) << json.message();
  ASSERT_EQ(*json, *r) << "iteration " << iteration;
}

// Values that sit on the edges of what a field accepts, and things that are no value at all.
const std::vector<std::string> kTrickyValues = {
    "0", "-0", "+0", "1", "-1", "+1", "0.5", "1.0000001", "0.9995", "1.001", "1e-400", "1e400", "-1e400",
    "4.9e-324", "1.7976931348623157e308", "nan", "-nan", "inf", "-inf", "NaN", "infinity", "0x10", "1e",
    ".", "+", "-", "--1", "1.0.0", "4294967295", "4294967296", "-4294967296", "18446744073709551616",
    std::string(400, '9'), "drill", "mirror", "Drill", "", " ", "\"drill\"", "#", "\xc2\xb5",
    std::string("\0", 1), "true", "null", "[]", "{}", "[1,0,0,0]", "[1,2,3]", "\"t_s\"", "\"pen\"",
    "\"pedal\":0", "\"samples\"", "\"\\u0000\"", "\"\\ud800\"", "1,2", "\n", "\r"};

// ---- CSV ------------------------------------------------------------------------------------

// Lines split at '\n' (which join() puts back), so that edits keep or move whole rows.
std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  for (size_t nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', start)) {
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  lines.push_back(text.substr(start));
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (size_t i = 0; i < lines.size(); ++i) out += (i ? "\n" : "") + lines[i];
  return out;
}

// One random row-level change: a field replaced by a tricky value, a line dropped, repeated, moved
// or added, or a line ending changed.
void mutateCsv(std::vector<std::string>& lines, std::mt19937& rng) {
  const size_t i = pick(rng, lines.size());
  switch (rng() % 6) {
    case 0: {  // one field of a row
      std::string& line = lines[i];
      std::vector<size_t> commas = {0};
      for (size_t c = 0; c < line.size(); ++c)
        if (line[c] == ',') commas.push_back(c + 1);
      const size_t f = pick(rng, commas.size());
      const size_t end = line.find(',', commas[f]);
      line.replace(commas[f], (end == std::string::npos ? line.size() : end) - commas[f],
                   kTrickyValues[pick(rng, kTrickyValues.size())]);
      break;
    }
    case 1: lines.erase(lines.begin() + std::ptrdiff_t(i)); break;
    case 2: lines.insert(lines.begin() + std::ptrdiff_t(pick(rng, lines.size() + 1)), lines[i]); break;
    case 3: std::swap(lines[i], lines[pick(rng, lines.size())]); break;
    case 4: {
      static const char* const kLines[] = {"# comment", "", "   ", "\t#", "\r", "t_s,pen", ",,,,,,,,,,"};
      lines.insert(lines.begin() + std::ptrdiff_t(pick(rng, lines.size() + 1)), kLines[rng() % std::size(kLines)]);
      break;
    }
    default: lines[i] += rng() % 2 ? "\r" : ",";
  }
  if (lines.empty()) lines.emplace_back();
}

void fuzzCsv(uint32_t seed, int iterations, bool byte_edits) {
  const std::string original = penPathCsv(seedPath());
  const std::vector<std::string> lines = splitLines(original);
  ASSERT_EQ(joinLines(lines), original);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0, json_accepted = 0, json_rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<std::string> l = lines;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) mutateCsv(l, rng);
    std::string text = joinLines(l);
    if (byte_edits) {
      std::vector<uint8_t> bytes(text.begin(), text.end());
      test::mutateBytesGeneric(bytes, rng);
      text.assign(bytes.begin(), bytes.end());
    }
    checkOutcome(parsePenPathCsv(text, kCsvWhere, fuzzLimits()), kCsvWhere, it, &accepted, &rejected);
    // The other reader must refuse CSV cleanly too.
    checkOutcome(parsePenPathJson(text, kJsonWhere, fuzzLimits()), kJsonWhere, it, &json_accepted, &json_rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
  EXPECT_EQ(json_accepted, 0);
}

// ---- JSON -----------------------------------------------------------------------------------

// Text cut into structural characters ({}[],:), whitespace, and the runs between them (numbers,
// strings, literals), so that an edit swaps one value or one piece of structure.
std::vector<std::string> splitJson(const std::string& text) {
  std::vector<std::string> pieces;
  const std::string structural = "{}[],: \n\t";
  size_t i = 0;
  while (i < text.size()) {
    if (structural.find(text[i]) != std::string::npos) {
      pieces.push_back(text.substr(i, 1));
      ++i;
      continue;
    }
    const size_t start = i;
    if (text[i] == '"') {  // a string, which may hold structural characters
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
      i = std::min(i + 1, text.size());
    } else {
      while (i < text.size() && structural.find(text[i]) == std::string::npos) ++i;
    }
    pieces.push_back(text.substr(start, i - start));
  }
  return pieces;
}

// One random piece-level change: a value replaced, a piece dropped or repeated, a run of pieces (a
// whole sample, often) dropped or repeated, or a structural character changed.
void mutateJson(std::vector<std::string>& pieces, std::mt19937& rng) {
  static const char* const kStructure[] = {"{", "}", "[", "]", ",", ":", " ", ""};
  if (pieces.empty()) {
    pieces.push_back(kTrickyValues[pick(rng, kTrickyValues.size())]);
    return;
  }
  const size_t i = pick(rng, pieces.size());
  switch (rng() % 5) {
    case 0: pieces[i] = kTrickyValues[pick(rng, kTrickyValues.size())]; break;
    case 1: pieces.erase(pieces.begin() + std::ptrdiff_t(i)); break;
    case 2: pieces.insert(pieces.begin() + std::ptrdiff_t(i), pieces[pick(rng, pieces.size())]); break;
    case 3: {
      const size_t n = std::min(pieces.size() - i, 1 + pick(rng, 60));
      if (rng() % 2) {
        pieces.erase(pieces.begin() + std::ptrdiff_t(i), pieces.begin() + std::ptrdiff_t(i + n));
      } else {
        const std::vector<std::string> run(pieces.begin() + std::ptrdiff_t(i), pieces.begin() + std::ptrdiff_t(i + n));
        pieces.insert(pieces.begin() + std::ptrdiff_t(i), run.begin(), run.end());
      }
      break;
    }
    default: pieces[i] = kStructure[rng() % std::size(kStructure)]; break;
  }
}

void fuzzJson(uint32_t seed, int iterations, bool byte_edits) {
  const std::string original = penPathJson(seedPath());
  const std::vector<std::string> pieces = splitJson(original);
  std::string joined;
  for (const std::string& p : pieces) joined += p;
  ASSERT_EQ(joined, original);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0, csv_accepted = 0, csv_rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<std::string> p = pieces;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) mutateJson(p, rng);
    std::string text;
    for (const std::string& s : p) text += s;
    if (byte_edits) {
      std::vector<uint8_t> bytes(text.begin(), text.end());
      test::mutateBytesGeneric(bytes, rng);
      text.assign(bytes.begin(), bytes.end());
    }
    checkOutcome(parsePenPathJson(text, kJsonWhere, fuzzLimits()), kJsonWhere, it, &accepted, &rejected);
    checkOutcome(parsePenPathCsv(text, kCsvWhere, fuzzLimits()), kCsvWhere, it, &csv_accepted, &csv_rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
  EXPECT_EQ(csv_accepted, 0);
}

TEST(PenPathFuzzTest, MutatedCsvRows) {
  fuzzCsv(20240611u, 6000, false);
}

TEST(PenPathFuzzTest, MutatedCsvRowsAndBytes) {
  fuzzCsv(4242u, 4000, true);
}

TEST(PenPathFuzzTest, MutatedJsonPieces) {
  fuzzJson(7u, 6000, false);
}

TEST(PenPathFuzzTest, MutatedJsonPiecesAndBytes) {
  fuzzJson(31337u, 4000, true);
}

}  // namespace
}  // namespace dentsim
