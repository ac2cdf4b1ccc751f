// Bounded, deterministic mutation fuzzing of the session reader: hostile bytes never crash it, accepted recordings are valid and encode back to themselves, and every failure is one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <xxhash.h>

#include "io/session_file.h"

#include "fuzz_mutations.h"
#include "test_sessions.h"

namespace dentsim {
namespace {

using test::pick;

const std::string kWhere = "fuzz.dses";

// Tight, so that a run of duplicated records could not make a case allocate much.
SessionReadLimits fuzzLimits() {
  SessionReadLimits limits;
  limits.max_steps = 64;
  limits.max_header_bytes = 1u << 16;
  limits.max_record_bytes = 1u << 12;
  return limits;
}

SessionStep seedStep(uint64_t k, uint8_t pens, uint32_t params_serial) {
  SessionStep s;
  s.step = k;
  s.wall_ns = int64_t(k) * 1'000'000;
  s.params_serial = params_serial;
  s.pens = pens;
  for (size_t r = 0; r < 2; ++r) {
    SessionPenReading& p = s.reading[r];
    p.grip = {{double(k), 2.5, -1.0}, Quat::fromAxisAngle({0, 1, 1}, 0.1 * double(k + r))};
    p.velocity = {0.1, -0.0, 3};
    p.angular_velocity = {0, 1e-300, 0};
    p.buttons = uint32_t(r + 1);
    p.pedal = r == 0 ? 0.5 : 0.0;
  }
  s.force_n = {Vec3{0.1, 0.2, -0.3}, Vec3{}};
  s.contacts = {uint32_t(k), 0};
  return s;
}

// Steps 3..6 with both pens, drill only and none (step 4 budgeted, so a schedule record follows it);
// parameter sets; a gap; device events; the end record.
SessionRecording seedRecording() {
  SessionRecording r;
  r.info = test::fullSessionInfo("molar.dvol", "built-in molar", R"({"k": 0.1, "b": [1, 2.5], "o": {"x": -0.0}})");
  r.steps = {seedStep(3, 0b11, 0), seedStep(4, 0b01, 1), seedStep(5, 0b00, 1), seedStep(9, 0b10, 2)};
  r.steps[1].schedule.clusters[0] = 2;
  r.steps[1].schedule.cuts = 0;
  r.params = {{1, 4, R"({"k": 0.2})"}, {2, 6, R"({"k": 0.3})"}};
  r.gaps = {{6, 3}};
  r.devices = {{4, 1, "fault", "HDAPI servo loop: communication error"}, {12, 1, "ready", ""}};
  r.end = SessionEnd{10, "fedcba9876543210", "completed"};
  return r;
}

// ---- structure-aware mutations --------------------------------------------------------------

// A file cut into its header (magic to header checksum) and its records, each whole.
struct Pieces {
  std::vector<uint8_t> header;
  std::vector<std::vector<uint8_t>> records;
};

Pieces split(const std::vector<uint8_t>& bytes) {
  Pieces p;
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  size_t at = 16 + size_t(length) + 8;
  p.header.assign(bytes.begin(), bytes.begin() + std::ptrdiff_t(at));
  while (at < bytes.size()) {
    std::memcpy(&length, bytes.data() + at + 4, 4);
    const size_t end = at + 12 + length;
    p.records.emplace_back(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(end));
    at = end;
  }
  return p;
}

std::vector<uint8_t> join(const Pieces& p) {
  std::vector<uint8_t> out = p.header;
  for (const std::vector<uint8_t>& r : p.records) out.insert(out.end(), r.begin(), r.end());
  return out;
}

// Recomputes a record's checksum, so that a change reaches the checks behind it.
void reseal(std::vector<uint8_t>& record) {
  if (record.size() < 12) return;
  const uint32_t sum = XXH32(record.data(), record.size() - 4, 0);
  std::memcpy(record.data() + record.size() - 4, &sum, 4);
}

// The same for the header's text.
void resealHeader(std::vector<uint8_t>& header) {
  if (header.size() < 24) return;
  const uint32_t length = uint32_t(header.size() - 24);
  std::memcpy(header.data() + 12, &length, 4);
  const uint64_t sum = XXH64(header.data() + 16, length, 0);
  std::memcpy(header.data() + 16 + length, &sum, 8);
}

// Values on the edges of what a field accepts.
const double kTrickyDoubles[] = {0.0, -0.0, 1.0, -1.0, 1.0005, 0.9985, 2.0, 0.5, 1e-300,
                                 std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
                                 std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity()};
const uint64_t kTrickyWords[] = {0, 1, 2, 3, 4, 5, 6, 9, 10, 255, 0xffffffffu, uint64_t{1} << 63,
                                 (uint64_t{1} << 63) - 1, ~uint64_t{0}};

// One change that keeps the checksums right: a word of a payload, a record dropped, repeated or
// moved, the record list cut, a kind changed, or a byte of the header's JSON.
void mutatePieces(Pieces& p, std::mt19937& rng) {
  const size_t i = pick(rng, p.records.size());
  switch (rng() % 7) {
    case 0:
    case 1: {  // a double or an integer at any offset of a payload
      if (p.records.empty()) return;
      std::vector<uint8_t>& r = p.records[i];
      if (r.size() < 12 + 8) return;
      const size_t at = 8 + pick(rng, r.size() - 12 - 7);
      if (rng() % 2) {
        const double v = kTrickyDoubles[rng() % std::size(kTrickyDoubles)];
        std::memcpy(r.data() + at, &v, 8);
      } else {
        const uint64_t v = kTrickyWords[rng() % std::size(kTrickyWords)];
        std::memcpy(r.data() + at, &v, 1 + pick(rng, 8));
      }
      reseal(r);
      return;
    }
    case 2:
      if (!p.records.empty()) p.records.erase(p.records.begin() + std::ptrdiff_t(i));
      return;
    case 3:
      if (!p.records.empty()) p.records.insert(p.records.begin() + std::ptrdiff_t(pick(rng, p.records.size() + 1)), p.records[i]);
      return;
    case 4:
      if (!p.records.empty()) std::swap(p.records[i], p.records[pick(rng, p.records.size())]);
      return;
    case 5:  // a kind, known or not
      if (!p.records.empty()) {
        p.records[i][0] = uint8_t(rng() % 7);
        reseal(p.records[i]);
      }
      return;
    default: {  // the header's JSON text
      if (p.header.size() <= 24) return;
      static const char kBytes[] = {'{', '}', '[', ']', ',', ':', '"', '0', '1', '9', '.', '-', 'e', ' ', 'x', '\\'};
      const size_t at = 16 + pick(rng, p.header.size() - 24);
      if (rng() % 2)
        p.header[at] = uint8_t(kBytes[rng() % std::size(kBytes)]);
      else
        p.header.erase(p.header.begin() + std::ptrdiff_t(at));
      resealHeader(p.header);
      return;
    }
  }
}

// ---- checks ---------------------------------------------------------------------------------

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

// Accepted recordings must hold what the reader promises and encode back to the same recording;
// rejections must be one line naming the source.
void checkOutcome(const Result<SessionRecording>& r, int iteration, int* accepted, int* rejected) {
  if (!r.ok()) {
    ++*rejected;
    test::assertOneLineRejection(r.message(), kWhere, iteration);
    return;
  }
  ++*accepted;
  const SessionRecording& rec = *r;
  if (!rec.truncation_warning.empty()) test::assertOneLineRejection(rec.truncation_warning, kWhere, iteration);
  ASSERT_LE(rec.steps.size(), fuzzLimits().max_steps) << "iteration " << iteration;
  ASSERT_TRUE(std::isfinite(rec.info.rate_hz) && rec.info.rate_hz >= 100 && rec.info.rate_hz <= 10000);
  ASSERT_FALSE(rec.info.drill_tool.empty()) << "iteration " << iteration;
  for (size_t i = 0; i < rec.params.size(); ++i) ASSERT_EQ(rec.params[i].serial, i + 1) << "iteration " << iteration;
  for (size_t i = 0; i < rec.steps.size(); ++i) {
    const SessionStep& s = rec.steps[i];
    if (i > 0) {
      ASSERT_GT(s.step, rec.steps[i - 1].step) << "iteration " << iteration;
    }
    ASSERT_EQ(s.pens & ~3u, 0u) << "iteration " << iteration;
    ASSERT_LE(s.params_serial, rec.params.size()) << "iteration " << iteration;
    for (size_t p = 0; p < 2; ++p) {
      ASSERT_TRUE(finite(s.force_n[p])) << "iteration " << iteration;
      if (!s.hasReading(p)) continue;
      const SessionPenReading& pen = s.reading[p];
      const Quat& q = pen.grip.rotation;
      ASSERT_TRUE(finite(pen.grip.position) && q.finite() && finite(pen.velocity) && finite(pen.angular_velocity));
      ASSERT_NEAR(std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z), 1.0, 1e-12) << "iteration " << iteration;
      ASSERT_TRUE(pen.pedal >= 0 && pen.pedal <= 1) << "iteration " << iteration;
    }
  }
  for (size_t i = 0; i < rec.devices.size(); ++i) {
    const SessionDeviceEvent& e = rec.devices[i];
    ASSERT_LE(e.pen, 1) << "iteration " << iteration;
    ASSERT_FALSE(e.state.empty()) << "iteration " << iteration;
    ASSERT_LE(e.reason.size(), 200u) << "iteration " << iteration;
    if (i > 0) {
      ASSERT_GE(e.step, rec.devices[i - 1].step) << "iteration " << iteration;
    }
  }
  // What was read encodes to a file that reads back the same, and encodes to the same bytes again.
  const std::vector<uint8_t> bytes = encodeSession(rec);
  const Result<SessionRecording> again = parseSession(bytes, kWhere, fuzzLimits());
  ASSERT_TRUE(again.ok()) << "iteration " << iteration << ": " << again.message();
  ASSERT_TRUE(again->truncation_warning.empty()) << again->truncation_warning;
  ASSERT_EQ(again->steps.size(), rec.steps.size()) << "iteration " << iteration;
  ASSERT_EQ(again->devices.size(), rec.devices.size()) << "iteration " << iteration;
  for (size_t i = 0; i < rec.steps.size(); ++i) {
    ASSERT_EQ(bits(again->steps[i].reading[0].grip.rotation.w), bits(rec.steps[i].reading[0].grip.rotation.w));
    ASSERT_EQ(again->steps[i].schedule, rec.steps[i].schedule) << "iteration " << iteration;
  }
  ASSERT_EQ(again->info.params_json, rec.info.params_json) << "iteration " << iteration;
  ASSERT_EQ(encodeSession(*again), bytes) << "iteration " << iteration;
}

void fuzz(uint32_t seed, int iterations, bool structured) {
  const std::vector<uint8_t> original = encodeSession(seedRecording());
  const Pieces pieces = split(original);
  ASSERT_EQ(join(pieces), original);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> bytes;
    if (structured) {
      Pieces p = pieces;
      const int edits = 1 + int(rng() % 3);
      for (int e = 0; e < edits; ++e) mutatePieces(p, rng);
      bytes = join(p);
    } else {
      bytes = original;
      const int edits = 1 + int(rng() % 3);
      for (int e = 0; e < edits; ++e) {
        // The format's own mutation: a cut after the header, as a crash leaves the file.
        if (!test::mutateBytesGeneric(bytes, rng) && bytes.size() > pieces.header.size())
          bytes.resize(pieces.header.size() + pick(rng, bytes.size() - pieces.header.size()));
      }
    }
    checkOutcome(parseSession(bytes, kWhere, fuzzLimits()), it, &accepted, &rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(SessionFuzzTest, MutatedBytes) {
  fuzz(20261122u, 6000, false);
}

TEST(SessionFuzzTest, MutatedRecordsWithChecksumsKept) {
  fuzz(4242u, 8000, true);
}

}  // namespace
}  // namespace dentsim
