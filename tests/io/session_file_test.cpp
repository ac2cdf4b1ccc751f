// Tests of src/io/session_file.cpp: bit-exact round trips, the writer's .part file and its bytes, truncation at every byte, corruption, and each validation error's one-line message.
#include "io/session_file.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <xxhash.h>

#include "test_sessions.h"
#include "test_support.h"

namespace dentsim {
namespace {

// ---- fixtures -------------------------------------------------------------------------------

constexpr double kTiny = std::numeric_limits<double>::denorm_min();
constexpr double kMax = std::numeric_limits<double>::max();

// A parameter set with doubles that a careless writer loses (no short binary form, near the
// bottom of the range, the classic 0.1 + 0.2), written as simParamsJson writes: dump(2) + "\n".
const std::string kParamsJson =
    "{\n  \"stiffness\": 0.1,\n  \"tiny\": 1e-300,\n  \"sum\": 0.30000000000000004,\n  \"zero\": -0.0,\n"
    "  \"subnormal\": 5e-324,\n  \"count\": 3,\n  \"nested\": {\n    \"k\": [\n      1.5,\n      2\n    ]\n  }\n}\n";

SessionInfo testInfo() {
  return test::fullSessionInfo("teeth/molar.dvol", "built-in molar, level 9, CPU voxelizer", kParamsJson);
}

SessionPenReading reading(double seed, double pedal) {
  SessionPenReading r;
  r.grip.position = {seed, -seed * 3, 0.1 + seed};
  r.grip.rotation = Quat::fromAxisAngle({1, 2, 3}, 0.3 + seed * 0.01);
  r.velocity = {0.5 * seed, -0.0, kTiny};
  r.angular_velocity = {1e-300, 0.1, -2.5};
  r.buttons = uint32_t(seed) | 0x80000000u;
  r.pedal = pedal;
  return r;
}

// Step k: the drill always reads, the mirror on odd steps; awkward doubles throughout.
SessionStep step(uint64_t k, uint32_t params_serial = 0) {
  SessionStep s;
  s.step = k;
  s.wall_ns = int64_t(k) * 1'000'003 - 5;
  s.params_serial = params_serial;
  s.pens = k % 2 ? 0b11 : 0b01;
  s.reading[0] = reading(double(k), 0.1);
  if (k % 2) s.reading[1] = reading(-double(k), 1.0);
  s.force_n[0] = {-0.0, kTiny, 0.1 * double(k)};
  s.force_n[1] = {kMax, -kMax, 1.0 / 3.0};
  s.contacts = {uint32_t(k), 0xffffffffu};
  return s;
}

// Steps 10..14, parameter set 1 from step 12, a gap of 3 (15..17), steps 18..19, parameter set 2
// from step 20 after the last step, and the end record.
SessionRecording testRecording() {
  SessionRecording r;
  r.info = testInfo();
  for (uint64_t k = 10; k <= 14; ++k) r.steps.push_back(step(k, k >= 12 ? 1 : 0));
  for (uint64_t k = 18; k <= 19; ++k) r.steps.push_back(step(k, 1));
  r.params = {{1, 12, R"({"stiffness": 0.2})"}, {2, 20, "{\"stiffness\":\n 1e-300}"}};
  r.gaps = {{15, 3}};
  r.end = SessionEnd{20, "fedcba9876543210", "completed"};
  return r;
}

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

void expectSameVec(const Vec3& a, const Vec3& b, const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bits(a[i]), bits(b[i])) << what << "[" << i << "]";
}

// Equal bit for bit: -0.0 differs from 0.0 here, unlike with ==.
void expectSameStep(const SessionStep& a, const SessionStep& b) {
  const std::string at = "step " + std::to_string(b.step);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.wall_ns, b.wall_ns) << at;
  EXPECT_EQ(a.params_serial, b.params_serial) << at;
  EXPECT_EQ(a.pens, b.pens) << at;
  for (size_t r = 0; r < 2; ++r) {
    if (b.hasReading(r)) {
      const SessionPenReading& x = a.reading[r];
      const SessionPenReading& y = b.reading[r];
      expectSameVec(x.grip.position, y.grip.position, at + " position");
      EXPECT_EQ(bits(x.grip.rotation.w), bits(y.grip.rotation.w)) << at;
      EXPECT_EQ(bits(x.grip.rotation.x), bits(y.grip.rotation.x)) << at;
      EXPECT_EQ(bits(x.grip.rotation.y), bits(y.grip.rotation.y)) << at;
      EXPECT_EQ(bits(x.grip.rotation.z), bits(y.grip.rotation.z)) << at;
      expectSameVec(x.velocity, y.velocity, at + " velocity");
      expectSameVec(x.angular_velocity, y.angular_velocity, at + " angular_velocity");
      EXPECT_EQ(x.buttons, y.buttons) << at;
      EXPECT_EQ(bits(x.pedal), bits(y.pedal)) << at;
    }
    expectSameVec(a.force_n[r], b.force_n[r], at + " force_n");
    EXPECT_EQ(a.contacts[r], b.contacts[r]) << at;
    EXPECT_EQ(a.schedule.clusters[r], b.schedule.clusters[r]) << at << " schedule.clusters[" << r << "]";
  }
  EXPECT_EQ(a.schedule.cuts, b.schedule.cuts) << at << " schedule.cuts";
}

void expectSameRecording(const SessionRecording& a, const SessionRecording& b) {
  EXPECT_EQ(a.info.created_utc, b.info.created_utc);
  EXPECT_EQ(a.info.program, b.info.program);
  EXPECT_EQ(bits(a.info.rate_hz), bits(b.info.rate_hz));
  EXPECT_EQ(a.info.task, b.info.task);
  EXPECT_EQ(a.info.tooth_hash, b.info.tooth_hash);
  EXPECT_EQ(a.info.tooth_file, b.info.tooth_file);
  EXPECT_EQ(a.info.tooth_source, b.info.tooth_source);
  EXPECT_EQ(a.info.tooth_level, b.info.tooth_level);
  EXPECT_EQ(bits(a.info.voxel_mm), bits(b.info.voxel_mm));
  EXPECT_EQ(a.info.drill_tool, b.info.drill_tool);
  EXPECT_EQ(a.info.mirror_tool, b.info.mirror_tool);
  EXPECT_EQ(a.info.params_json, b.info.params_json);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t i = 0; i < a.steps.size(); ++i) expectSameStep(a.steps[i], b.steps[i]);
  ASSERT_EQ(a.params.size(), b.params.size());
  for (size_t i = 0; i < a.params.size(); ++i) {
    EXPECT_EQ(a.params[i].serial, b.params[i].serial);
    EXPECT_EQ(a.params[i].from_step, b.params[i].from_step);
    EXPECT_EQ(a.params[i].params_json, b.params[i].params_json);
  }
  ASSERT_EQ(a.gaps.size(), b.gaps.size());
  for (size_t i = 0; i < a.gaps.size(); ++i) {
    EXPECT_EQ(a.gaps[i].first_step, b.gaps[i].first_step);
    EXPECT_EQ(a.gaps[i].steps, b.gaps[i].steps);
  }
  ASSERT_EQ(a.end.has_value(), b.end.has_value());
  if (a.end) {
    EXPECT_EQ(a.end->steps, b.end->steps);
    EXPECT_EQ(a.end->final_hash, b.end->final_hash);
    EXPECT_EQ(a.end->reason, b.end->reason);
  }
}

const std::string kWhere = "s.dses";

Result<SessionRecording> parse(const std::vector<uint8_t>& bytes, const SessionReadLimits& limits = {}) {
  return parseSession(bytes, kWhere, limits);
}

// The whole message, which must be one line.
void expectError(const Result<SessionRecording>& r, const std::string& message) {
  ASSERT_FALSE(r.ok()) << "expected: " << message;
  EXPECT_EQ(r.message(), message);
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// ---- hand-made files --------------------------------------------------------------------------

template <class T>
void put(std::vector<uint8_t>& out, T v) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &v, sizeof(T));
}

// Magic, version, header text and its checksum, as docs/SESSIONS.md lays them out.
std::vector<uint8_t> rawHeader(const std::string& json, uint32_t version = kSessionFileVersion) {
  std::vector<uint8_t> out = {'D', 'S', 'E', 'S', 'S', 'I', 'O', 'N'};
  put<uint32_t>(out, version);
  put<uint32_t>(out, uint32_t(json.size()));
  out.insert(out.end(), json.begin(), json.end());
  put<uint64_t>(out, XXH64(json.data(), json.size(), 0));
  return out;
}

// A record with a correct checksum, whatever its contents.
void putRecord(std::vector<uint8_t>& out, uint8_t kind, const std::vector<uint8_t>& payload) {
  const size_t start = out.size();
  out.push_back(kind);
  out.insert(out.end(), 3, 0);
  put<uint32_t>(out, uint32_t(payload.size()));
  out.insert(out.end(), payload.begin(), payload.end());
  put<uint32_t>(out, XXH32(out.data() + start, out.size() - start, 0));
}

// The header text encodeSession writes for the test info, as a JSON tree to edit.
nlohmann::ordered_json headerJson() {
  const std::vector<uint8_t> bytes = encodeSession(SessionRecording{testInfo(), {}, {}, {}, {}, {}, {}});
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return nlohmann::ordered_json::parse(bytes.begin() + 16, bytes.begin() + 16 + length);
}

std::vector<uint8_t> headerOnly() { return encodeSession(SessionRecording{testInfo(), {}, {}, {}, {}, {}, {}}); }

// Byte offsets of each record (and, last, the end of the file).
std::vector<size_t> recordStarts(const std::vector<uint8_t>& bytes) {
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  std::vector<size_t> starts;
  size_t at = 16 + size_t(length) + 8;
  while (at < bytes.size()) {
    starts.push_back(at);
    std::memcpy(&length, bytes.data() + at + 4, 4);
    at += 12 + size_t(length);
  }
  starts.push_back(at);
  return starts;
}

std::vector<uint8_t> gapPayload(uint64_t first, uint64_t steps) {
  std::vector<uint8_t> p;
  put<uint64_t>(p, first);
  put<uint64_t>(p, steps);
  return p;
}

std::vector<uint8_t> paramsPayload(uint32_t serial, uint64_t from_step, const std::string& json) {
  std::vector<uint8_t> p;
  put<uint32_t>(p, serial);
  put<uint64_t>(p, from_step);
  p.insert(p.end(), json.begin(), json.end());
  return p;
}

// A recording of the test info with the given steps and nothing else.
std::vector<uint8_t> encodeSteps(const std::vector<SessionStep>& steps) {
  SessionRecording r;
  r.info = testInfo();
  r.steps = steps;
  return encodeSession(r);
}

// ---- round trips ----------------------------------------------------------------------------

TEST(SessionFileTest, RoundTripIsBitExact) {
  const SessionRecording original = testRecording();
  const Result<SessionRecording> back = parse(encodeSession(original));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(back->truncation_warning.empty()) << back->truncation_warning;
  expectSameRecording(*back, original);
  // Encoding what was read gives the same bytes again.
  EXPECT_EQ(encodeSession(*back), encodeSession(original));
}

TEST(SessionFileTest, HeaderParamsKeepEveryDouble) {
  const Result<SessionRecording> back = parse(encodeSession(testRecording()));
  ASSERT_TRUE(back.ok()) << back.message();
  // The header's parameter set comes back as dump(2) + "\n", which is simParamsJson's own form.
  EXPECT_EQ(back->info.params_json, kParamsJson);
  const nlohmann::json params = nlohmann::json::parse(back->info.params_json);
  EXPECT_EQ(bits(params["stiffness"].get<double>()), bits(0.1));
  EXPECT_EQ(bits(params["tiny"].get<double>()), bits(1e-300));
  EXPECT_EQ(bits(params["sum"].get<double>()), bits(0.1 + 0.2));
  EXPECT_EQ(bits(params["zero"].get<double>()), bits(-0.0));
  EXPECT_EQ(bits(params["subnormal"].get<double>()), bits(kTiny));
  EXPECT_TRUE(params["count"].is_number_integer());

  // Text in another layout is stored as the same object, in the same key order.
  SessionRecording compact = testRecording();
  compact.info.params_json = R"({"b":0.30000000000000004,"a":1e-300})";
  const Result<SessionRecording> again = parse(encodeSession(compact));
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(again->info.params_json, "{\n  \"b\": 0.30000000000000004,\n  \"a\": 1e-300\n}\n");
}

TEST(SessionFileTest, AGuideIsOptionalAndReadsBackAsTheSameObject) {
  // Unguided: no "guide" key at all, so unguided files are what they were before guidance existed.
  const std::vector<uint8_t> plain = encodeSession(testRecording());
  EXPECT_EQ(std::string(plain.begin(), plain.end()).find("\"guide\""), std::string::npos);
  SessionRecording guided = testRecording();
  guided.info.guide_json = R"({"source":"pro.dses","stiffness_n_per_mm":0.30000000000000004,"points":[[1e-300,2,3]]})";
  const Result<SessionRecording> back = parse(encodeSession(guided));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->info.guide_json, guided.info.guide_json);
  EXPECT_EQ(encodeSession(*back), encodeSession(guided));
  // A guide that is not an object is a header error, named.
  guided.info.guide_json = "5";
  const Result<SessionRecording> bad = parse(encodeSession(guided));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("guide: expected an object"), std::string::npos) << bad.message();
  test::TempDir dir;
  SessionWriter w;
  const Status st = w.open(dir.file("s.dses"), guided.info);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message(), dir.file("s.dses") + ": header: guide: the guide is not a JSON object");
}

TEST(SessionFileTest, DrillOnlyAndNoStepsRoundTrip) {
  // Only the header and the end record: a session stopped before its first step.
  SessionRecording r;
  r.info = testInfo();
  r.info.mirror_tool = "";
  r.info.task = "";
  r.end = SessionEnd{0, "0000000000000000", ""};
  Result<SessionRecording> back = parse(encodeSession(r));
  ASSERT_TRUE(back.ok()) << back.message();
  expectSameRecording(*back, r);

  // Drill-only steps (193-byte payloads) starting at step 0.
  r.end.reset();
  for (uint64_t k = 0; k < 3; ++k) {
    r.steps.push_back(step(2 * k));
    r.steps.back().step = k;
  }
  back = parse(encodeSession(r));
  ASSERT_TRUE(back.ok()) << back.message();
  expectSameRecording(*back, r);
}

TEST(SessionFileTest, RotationsAreMadeUnitUnlessUnitToRounding) {
  std::vector<SessionStep> steps = {step(0), step(1)};
  steps[0].reading[0].grip.rotation = Quat{1.0005, 0, 0, 0};                     // 5e-4 off: accepted, normalised
  steps[1].reading[0].grip.rotation = Quat{0.1, 0.2, 0.3, 0.4}.normalized();  // unit to rounding: kept
  const Result<SessionRecording> back = parse(encodeSteps(steps));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->steps[0].reading[0].grip.rotation, (Quat{1, 0, 0, 0}));
  EXPECT_EQ(back->steps[1].reading[0].grip.rotation, steps[1].reading[0].grip.rotation);
}

// ---- the writer -----------------------------------------------------------------------------

TEST(SessionFileTest, WriterBytesEqualEncodeSession) {
  const SessionRecording r = testRecording();
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  {
    SessionWriter w;
    ASSERT_TRUE(w.open(path, r.info).ok());
    EXPECT_TRUE(w.isOpen());
    EXPECT_EQ(w.partPath(), path + ".part");
    // The calls in the order encodeSession documents, flushed at odd places.
    w.add(r.steps[0]);
    w.add(r.steps[1]);
    ASSERT_TRUE(w.flush().ok());
    w.add(r.params[0]);
    w.add(r.steps[2]);
    w.add(r.steps[3]);
    ASSERT_TRUE(w.sync().ok());
    w.add(r.steps[4]);
    w.add(r.gaps[0]);
    w.add(r.steps[5]);
    w.add(r.steps[6]);
    w.add(r.params[1]);
    const Status done = w.finish(*r.end);
    ASSERT_TRUE(done.ok()) << done.message();
    EXPECT_FALSE(w.isOpen());
    EXPECT_EQ(w.bytesWritten(), encodeSession(r).size());
  }
  EXPECT_EQ(fileBytes(path), encodeSession(r));
  const Result<SessionRecording> back = readSessionFile(path);
  ASSERT_TRUE(back.ok()) << back.message();
  expectSameRecording(*back, r);
}

TEST(SessionFileTest, BytesWrittenCountsWhatWasFlushed) {
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  SessionWriter w;
  ASSERT_TRUE(w.open(path, testInfo()).ok());
  const uint64_t header = w.bytesWritten();
  EXPECT_EQ(header, headerOnly().size());
  EXPECT_EQ(std::filesystem::file_size(path + ".part"), header);  // open() flushed the header
  w.add(step(0));                                                 // buffered only
  EXPECT_EQ(w.bytesWritten(), header);
  ASSERT_TRUE(w.flush().ok());
  EXPECT_EQ(w.bytesWritten(), header + 12 + 193);  // frame, drill-only payload, checksum
  EXPECT_EQ(std::filesystem::file_size(path + ".part"), header + 12 + 193);
}

TEST(SessionFileTest, PartFileUntilFinishLeavesTheOldFileAlone) {
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  writeBytes(path, {'o', 'l', 'd'});
  SessionWriter w;
  ASSERT_TRUE(w.open(path, testInfo()).ok());
  EXPECT_TRUE(std::filesystem::exists(path + ".part"));
  w.add(step(0));
  ASSERT_TRUE(w.sync().ok());
  EXPECT_EQ(fileBytes(path), (std::vector<uint8_t>{'o', 'l', 'd'}));
  // What was flushed already reads as a session that stopped without its end record.
  const Result<SessionRecording> part = readSessionFile(path + ".part");
  ASSERT_TRUE(part.ok()) << part.message();
  EXPECT_EQ(part->steps.size(), 1u);
  EXPECT_FALSE(part->end.has_value());

  ASSERT_TRUE(w.finish(SessionEnd{1, "0123456789abcdef", "stopped"}).ok());
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
  const Result<SessionRecording> done = readSessionFile(path);
  ASSERT_TRUE(done.ok()) << done.message();
  EXPECT_EQ(done->steps.size(), 1u);
  ASSERT_TRUE(done->end.has_value());
  EXPECT_EQ(done->end->reason, "stopped");
}

TEST(SessionFileTest, WriterDestroyedWithoutFinishLeavesAReadablePart) {
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  {
    SessionWriter w;
    ASSERT_TRUE(w.open(path, testInfo()).ok());
    w.add(step(4));
    ASSERT_TRUE(w.flush().ok());
    w.add(step(5));  // buffered: the destructor hands it to the file
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  const Result<SessionRecording> part = readSessionFile(path + ".part");
  ASSERT_TRUE(part.ok()) << part.message();
  ASSERT_EQ(part->steps.size(), 2u);
  expectSameStep(part->steps[1], step(5));
  EXPECT_FALSE(part->end.has_value());
  EXPECT_TRUE(part->truncation_warning.empty());
}

TEST(SessionFileTest, OpenNamesAMissingDirectory) {
  test::TempDir dir;
  const std::string path = dir.file("no/such/dir/s.dses");
  SessionWriter w;
  const Status s = w.open(path, testInfo());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), path + ".part: cannot create: No such file or directory");
  EXPECT_FALSE(w.isOpen());
}

TEST(SessionFileTest, OpenReportsAFullDisk) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  std::filesystem::create_symlink("/dev/full", path + ".part");  // every write fails with ENOSPC
  SessionWriter w;
  const Status s = w.open(path, testInfo());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), path + ".part: write failed: No space left on device");
  EXPECT_FALSE(w.isOpen());
}

TEST(SessionFileTest, OpenRefusesAHeaderThatWouldNotRead) {
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  SessionInfo info = testInfo();
  info.rate_hz = 50;
  SessionWriter w;
  Status s = w.open(path, info);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), path + ": header: rate_hz: 50 Hz is outside [100, 10000]");
  info = testInfo();
  info.params_json = "[1, 2]";
  s = w.open(path, info);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), path + ": header: params: the parameter set is not a JSON object");
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
}

// ---- truncation and corruption --------------------------------------------------------------

// A crash can cut the file anywhere: inside the header it is an error, after it the reader keeps
// every whole record and says so exactly when the cut is not at a record boundary.
TEST(SessionFileTest, TruncationAtEveryByteKeepsAPrefix) {
  const SessionRecording original = testRecording();
  const std::vector<uint8_t> bytes = encodeSession(original);
  const std::vector<size_t> starts = recordStarts(bytes);
  ASSERT_EQ(starts.back(), bytes.size());
  for (size_t cut = 0; cut <= bytes.size(); ++cut) {
    const std::vector<uint8_t> prefix(bytes.begin(), bytes.begin() + std::ptrdiff_t(cut));
    const Result<SessionRecording> r = parse(prefix);
    if (cut < starts.front()) {
      ASSERT_FALSE(r.ok()) << "cut at " << cut;
      if (cut > 0) {
        EXPECT_NE(r.message().find("cut off at byte " + std::to_string(cut)), std::string::npos) << r.message();
      }
      continue;
    }
    ASSERT_TRUE(r.ok()) << "cut at " << cut << ": " << r.message();
    const bool boundary = std::find(starts.begin(), starts.end(), cut) != starts.end();
    EXPECT_EQ(r->truncation_warning.empty(), boundary) << "cut at " << cut << ": " << r->truncation_warning;
    if (!boundary) {
      const std::string expected_start = kWhere + ": cut off at byte " + std::to_string(cut) + " inside record ";
      EXPECT_EQ(r->truncation_warning.rfind(expected_start, 0), 0u) << r->truncation_warning;
      EXPECT_NE(r->truncation_warning.find("read " + std::to_string(r->steps.size()) + " steps"), std::string::npos)
          << r->truncation_warning;
    }
    ASSERT_LE(r->steps.size(), original.steps.size());
    for (size_t i = 0; i < r->steps.size(); ++i) expectSameStep(r->steps[i], original.steps[i]);
    ASSERT_LE(r->params.size(), original.params.size());
    ASSERT_LE(r->gaps.size(), original.gaps.size());
    EXPECT_EQ(r->end.has_value(), cut == bytes.size());
  }
}

TEST(SessionFileTest, DamagedLastRecordIsATruncation) {
  // A crash that leaves the last record's bytes in place but not their content (a page of zeros).
  std::vector<uint8_t> bytes = encodeSteps({step(0), step(1), step(2)});
  bytes[bytes.size() - 20] ^= 0xff;
  const Result<SessionRecording> r = parse(bytes);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->steps.size(), 2u);
  const std::vector<size_t> starts = recordStarts(bytes);
  EXPECT_EQ(r->truncation_warning, kWhere + ": cut off at byte " + std::to_string(bytes.size()) + " inside record 3 (which starts at byte " +
                                       std::to_string(starts[2]) + "); read 2 steps");
}

TEST(SessionFileTest, FlippedByteInAMiddleRecordIsCorruption) {
  std::vector<uint8_t> bytes = encodeSession(testRecording());
  const std::vector<size_t> starts = recordStarts(bytes);
  bytes[starts[2] + 30] ^= 0x04;  // inside record 3's payload
  expectError(parse(bytes), kWhere + ": record 3 at byte " + std::to_string(starts[2]) +
                                ": checksum mismatch: the file is corrupt");
}

TEST(SessionFileTest, FlippedHeaderByteIsCorruption) {
  std::vector<uint8_t> bytes = encodeSession(testRecording());
  bytes[40] ^= 0x01;
  expectError(parse(bytes), kWhere + ": header checksum mismatch: the file is corrupt");
}

TEST(SessionFileTest, ForeignFilesAreNotSessions) {
  const std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
  expectError(parse(png), kWhere + ": is not a dentsim session file (no DSESSION magic)");
  const std::string stl = "solid tooth\n facet normal 0 0 1\n";
  expectError(parse(std::vector<uint8_t>(stl.begin(), stl.end())),
              kWhere + ": is not a dentsim session file (no DSESSION magic)");
  std::vector<uint8_t> dvol = {'D', 'E', 'N', 'T', 'S', 'I', 'M', 'V'};
  dvol.resize(224);
  expectError(parse(dvol), kWhere + ": is not a dentsim session file (no DSESSION magic)");
  expectError(parse({}), kWhere + ": is not a dentsim session file (empty)");
  expectError(parse({'{', '}'}), kWhere + ": is not a dentsim session file (only 2 bytes)");
  expectError(parse({'D', 'S', 'E'}), kWhere + ": cut off at byte 3 inside the header");
}

TEST(SessionFileTest, ReadSessionFileNamesThePath) {
  test::TempDir dir;
  const std::string path = dir.file("missing.dses");
  const Result<SessionRecording> missing = readSessionFile(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.message(), path + ": cannot open: No such file or directory");

  const std::string big = dir.file("big.dses");
  writeBytes(big, encodeSession(testRecording()));
  SessionReadLimits limits;
  limits.max_bytes = 100;
  const Result<SessionRecording> r = readSessionFile(big, limits);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(big + ": file of ", 0), 0u) << r.message();
  EXPECT_NE(r.message().find("exceeds the limit of 100 bytes"), std::string::npos) << r.message();
}

// ---- validation messages --------------------------------------------------------------------

// Where record n starts in the file encodeSteps writes for `steps`.
std::string recordAt(const std::vector<uint8_t>& bytes, size_t n) {
  return "record " + std::to_string(n) + " at byte " + std::to_string(recordStarts(bytes)[n - 1]);
}

TEST(SessionFileTest, RefusesANonUnitRotation) {
  std::vector<SessionStep> steps = {step(7), step(8)};
  steps[0].reading[1].grip.rotation = Quat{1, 1, 0, 0};
  const std::vector<uint8_t> bytes = encodeSteps(steps);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) +
                                ": step 7: pen 1 (mirror) rotation: norm 1.4142135623730951 is not within 0.001 of 1 "
                                "(not a unit quaternion)");
}

TEST(SessionFileTest, RefusesNonFiniteNumbers) {
  std::vector<SessionStep> steps = {step(7)};
  steps[0].reading[0].velocity.y = std::numeric_limits<double>::quiet_NaN();
  std::vector<uint8_t> bytes = encodeSteps(steps);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": step 7: pen 0 (drill) velocity[1]: not finite (nan)");
  steps[0] = step(7);
  steps[0].force_n[1].z = -std::numeric_limits<double>::infinity();
  bytes = encodeSteps(steps);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": step 7: pen 1 force_n[2]: not finite (-inf)");
}

TEST(SessionFileTest, RefusesAPedalOutsideZeroToOne) {
  std::vector<SessionStep> steps = {step(2), step(3)};
  steps[1].reading[0].pedal = 1.5;
  const std::vector<uint8_t> bytes = encodeSteps(steps);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": step 3: pen 0 (drill) pedal: 1.5 is outside [0, 1]");
}

TEST(SessionFileTest, RefusesUnknownPenBits) {
  std::vector<SessionStep> steps = {step(2)};
  steps[0].pens = 0b101;
  const std::vector<uint8_t> bytes = encodeSteps(steps);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) +
                                ": step 2: pens 5 has bits other than 0 (drill) and 1 (mirror) set");
}

TEST(SessionFileTest, RefusesAStepPayloadOfTheWrongLength) {
  std::vector<uint8_t> bytes = headerOnly();
  std::vector<uint8_t> payload;
  put<uint64_t>(payload, 3);
  put<int64_t>(payload, 0);
  put<uint32_t>(payload, 0);
  put<uint8_t>(payload, 0b11);
  payload.resize(77);  // what a step without readings takes
  putRecord(bytes, 1, payload);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": step 3: payload of 77 bytes, expected 309 for pens 3");
}

TEST(SessionFileTest, RefusesStepsOutOfOrder) {
  const std::vector<uint8_t> bytes = encodeSteps({step(37), step(38), step(40)});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) + ": step 40 follows step 38");
  const std::vector<uint8_t> back = encodeSteps({step(37), step(37)});
  expectError(parse(back), kWhere + ": " + recordAt(back, 2) + ": step 37 follows step 37");
}

TEST(SessionFileTest, GapsMustJoinTheSteps) {
  SessionRecording r;
  r.info = testInfo();
  r.steps = {step(38), step(42)};
  r.gaps = {{39, 3}};
  ASSERT_TRUE(parse(encodeSession(r)).ok());

  r.steps = {step(38), step(43)};  // the gap covers 39..41
  std::vector<uint8_t> bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": step 43 follows a gap of 3 steps from step 39 (expected 42)");

  r.steps = {step(38), step(42)};
  r.gaps = {{40, 2}};  // leaves 39 out
  bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": gap from step 40 follows step 38");

  bytes = encodeSteps({step(38)});
  putRecord(bytes, 3, gapPayload(39, 0));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": gap from step 39: no steps");
}

TEST(SessionFileTest, ParamsSerialsCountUpAndComeFirst) {
  SessionRecording r;
  r.info = testInfo();
  r.steps = {step(5, 0), step(6, 1)};
  r.params = {{2, 6, "{}"}};
  std::vector<uint8_t> bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": params serial 2: expected serial 1 (the first)");

  r.params = {{1, 6, "{}"}, {3, 7, "{}"}};
  r.steps.push_back(step(7, 1));
  bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 4) + ": params serial 3: expected serial 2 (after 1)");

  // A step may only use a parameter set read before it.
  r.params = {};
  r.steps = {step(5, 0), step(6, 1)};
  bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) +
                                ": step 6: params serial 1 was not read before it (the last is 0)");
}

TEST(SessionFileTest, ParamsFromStepMustBeTheNextStep) {
  std::vector<uint8_t> bytes = encodeSteps({step(5)});
  putRecord(bytes, 2, paramsPayload(1, 7, "{}"));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": params serial 1 from step 7 follows step 5");

  // Before any step the from_step is checked against the step that follows.
  bytes = headerOnly();
  putRecord(bytes, 2, paramsPayload(1, 7, "{}"));
  std::vector<uint8_t> with_step = encodeSteps({step(8, 1)});
  const std::vector<size_t> starts = recordStarts(with_step);
  bytes.insert(bytes.end(), with_step.begin() + std::ptrdiff_t(starts[0]), with_step.end());
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) +
                                ": step 8 follows params serial 1, which begins at step 7");

  bytes = encodeSteps({step(5)});
  putRecord(bytes, 2, paramsPayload(1, 6, "[1]"));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": params serial 1: the parameter set is not a JSON object");
}

TEST(SessionFileTest, RefusesAnUnknownRecordKind) {
  std::vector<uint8_t> bytes = encodeSteps({step(5)});
  putRecord(bytes, 9, {1, 2, 3});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 2) + ": unknown record kind 9");
}

std::vector<uint8_t> devicePayload(uint64_t step, uint8_t pen, const std::string& state, const std::string& reason) {
  std::vector<uint8_t> p;
  put<uint64_t>(p, step);
  put<uint8_t>(p, pen);
  put<uint16_t>(p, uint16_t(state.size()));
  p.insert(p.end(), state.begin(), state.end());
  put<uint16_t>(p, uint16_t(reason.size()));
  p.insert(p.end(), reason.begin(), reason.end());
  return p;
}

// A pen's device failing mid-session and coming back: read back as written, in step order, by the
// writer and by encodeSession alike, and never in the way of the steps around it.
TEST(SessionFileTest, DeviceEventsRoundTripBetweenTheStepsTheyCameBefore) {
  SessionRecording r;
  r.info = testInfo();
  for (uint64_t k = 10; k < 15; ++k) r.steps.push_back(step(k));
  r.devices.push_back({12, 1, "fault", "HDAPI servo loop: communication error (HD error 0x0302, internal 7)"});
  r.devices.push_back({12, 0, "fault", ""});
  r.devices.push_back({40, 1, "ready", ""});  // after the last step: written at the end
  r.end = SessionEnd{5, "0123456789abcdef", "stopped"};
  const std::vector<uint8_t> bytes = encodeSession(r);
  const Result<SessionRecording> back = parse(bytes);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->devices.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back->devices[i].step, r.devices[i].step);
    EXPECT_EQ(back->devices[i].pen, r.devices[i].pen);
    EXPECT_EQ(back->devices[i].state, r.devices[i].state);
    EXPECT_EQ(back->devices[i].reason, r.devices[i].reason);
  }
  EXPECT_EQ(back->steps.size(), 5u);
  EXPECT_EQ(encodeSession(*back), bytes);
  // Records: header, step 10, step 11, the two events, step 12 ...: the events come just before step 12.
  const std::vector<size_t> starts = recordStarts(bytes);
  EXPECT_EQ(bytes[starts[2]], 5);
  EXPECT_EQ(bytes[starts[3]], 5);
  EXPECT_EQ(bytes[starts[4]], 1);
  // The writer, given the same calls in that order, writes the same bytes.
  test::TempDir dir;
  const std::string path = dir.file("d.dses");
  SessionWriter w;
  ASSERT_TRUE(w.open(path, r.info).ok());
  w.add(r.steps[0]);
  w.add(r.steps[1]);
  w.add(r.devices[0]);
  w.add(r.devices[1]);
  for (size_t k = 2; k < 5; ++k) w.add(r.steps[k]);
  w.add(r.devices[2]);
  ASSERT_TRUE(w.finish(*r.end).ok());
  EXPECT_EQ(fileBytes(path), bytes);
}

TEST(SessionFileTest, RefusesDeviceEventsThatAreMalformedOrOutOfOrder) {
  const auto with = [](const std::vector<std::vector<uint8_t>>& payloads) {
    std::vector<uint8_t> bytes = encodeSteps({step(5), step(6)});
    for (const auto& p : payloads) putRecord(bytes, 5, p);
    return bytes;
  };
  auto bytes = with({devicePayload(6, 2, "fault", "")});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": device event at step 6: pen 2 (expected 0, the drill, or 1, the mirror)");
  bytes = with({devicePayload(6, 0, "", "")});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": device event at step 6: state \"\" is not a short printable word");
  bytes = with({devicePayload(6, 0, "fault", "a\nb")});
  EXPECT_FALSE(parse(bytes).ok());
  bytes = with({devicePayload(6, 0, "fault", ""), devicePayload(5, 1, "fault", "")});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 4) + ": device event at step 5 comes after one at step 6");
  bytes = with({devicePayload(6, 0, "fault", ""), devicePayload(6, 1, "fault", "")});
  SessionReadLimits one;
  one.max_device_events = 1;
  expectError(parseSession(bytes, kWhere, one),
              kWhere + ": " + recordAt(bytes, 4) + ": more than 1 device events, the limit for one session");
  std::vector<uint8_t> cut = devicePayload(6, 0, "fault", "why");
  cut.pop_back();
  bytes = with({cut});
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": device payload of 20 bytes does not match its string lengths");
}

TEST(SessionFileTest, RefusesNonZeroReservedBytes) {
  std::vector<uint8_t> record = {3, 0, 1, 0};  // a gap record with a stray bit after its kind
  put<uint32_t>(record, 16);
  const std::vector<uint8_t> payload = gapPayload(1, 2);
  record.insert(record.end(), payload.begin(), payload.end());
  put<uint32_t>(record, XXH32(record.data(), record.size(), 0));
  std::vector<uint8_t> bytes = headerOnly();
  bytes.insert(bytes.end(), record.begin(), record.end());
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": the three bytes after the record kind are not zero");
}

TEST(SessionFileTest, RefusesRecordsAfterTheEnd) {
  SessionRecording r;
  r.info = testInfo();
  r.steps = {step(1)};
  r.end = SessionEnd{2, "0123456789abcdef", "completed"};
  std::vector<uint8_t> bytes = encodeSession(r);
  const std::vector<uint8_t> more = encodeSteps({step(2)});
  bytes.insert(bytes.end(), more.begin() + std::ptrdiff_t(recordStarts(more)[0]), more.end());
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) + ": data after the end record");
}

TEST(SessionFileTest, RefusesABadEndRecord) {
  SessionRecording r;
  r.info = testInfo();
  r.end = SessionEnd{0, "0123456789ABCDEF", "completed"};
  std::vector<uint8_t> bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) +
                                ": end: final hash \"0123456789ABCDEF\" is not 16 lower-case hex digits");
  r.end = SessionEnd{0, "0123456789abcdef", "tab\there"};
  bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": end: reason \"tab\\x09here\" is not printable ASCII");
  r.end = SessionEnd{0, "0123456789abcdef", std::string(201, 'x')};
  bytes = encodeSession(r);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) + ": end: reason of 201 bytes is longer than 200");
}

// ---- schedules (budgeted steps) ------------------------------------------------------------

constexpr uint32_t kAll = SessionSchedule::kAll;
// The framing docs/SESSIONS.md gives: kind, three zeros and length; the checksum after the payload.
constexpr size_t kFrameBytes = 1 + 3 + 4;
constexpr size_t kRecordHashBytes = 4;
constexpr size_t kSchedulePayloadBytes = 8 + 2 * 4 + 4;  // step, clusters of both pens, cuts
constexpr size_t kScheduleRecordBytes = kFrameBytes + kSchedulePayloadBytes + kRecordHashBytes;
static_assert(kScheduleRecordBytes == 32);

SessionSchedule schedule(uint32_t drill_clusters, uint32_t mirror_clusters, uint32_t cuts) {
  SessionSchedule s;
  s.clusters = {drill_clusters, mirror_clusters};
  s.cuts = cuts;
  return s;
}

std::vector<uint8_t> schedulePayload(uint64_t step, uint32_t drill_clusters, uint32_t mirror_clusters, uint32_t cuts) {
  std::vector<uint8_t> p;
  put<uint64_t>(p, step);
  put<uint32_t>(p, drill_clusters);
  put<uint32_t>(p, mirror_clusters);
  put<uint32_t>(p, cuts);
  return p;
}

// testRecording() with four of its seven steps budgeted: each field cut short alone, all three at
// once, and 0 (a step that reached nothing), which is a schedule like any other; steps 11, 13 and
// 19 did all their work.
SessionRecording scheduledRecording() {
  SessionRecording r = testRecording();
  r.steps[0].schedule = schedule(3, kAll, kAll);   // step 10: the drill's pass stopped after 3 clusters
  r.steps[2].schedule = schedule(kAll, 0, kAll);   // step 12: the mirror's pass reached none
  r.steps[4].schedule = schedule(kAll, kAll, 0);   // step 14: every cut job left for later
  r.steps[5].schedule = schedule(17, 2, 5);        // step 18: all three
  return r;
}

TEST(SessionFileTest, SchedulesRoundTripThroughTheWriterAndEncodeSession) {
  const SessionRecording r = scheduledRecording();
  const std::vector<uint8_t> encoded = encodeSession(r);
  const Result<SessionRecording> back = parse(encoded);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(back->truncation_warning.empty()) << back->truncation_warning;
  expectSameRecording(*back, r);
  for (size_t i = 0; i < r.steps.size(); ++i) EXPECT_EQ(back->steps[i].schedule, r.steps[i].schedule) << "step " << r.steps[i].step;
  EXPECT_EQ(encodeSession(*back), encoded);

  // The writer, given the calls in encodeSession's order, writes the same bytes.
  test::TempDir dir;
  const std::string path = dir.file("s.dses");
  SessionWriter w;
  ASSERT_TRUE(w.open(path, r.info).ok());
  w.add(r.steps[0]);
  w.add(r.steps[1]);
  w.add(r.params[0]);
  for (size_t i = 2; i < 5; ++i) w.add(r.steps[i]);
  w.add(r.gaps[0]);
  w.add(r.steps[5]);
  w.add(r.steps[6]);
  w.add(r.params[1]);
  ASSERT_TRUE(w.finish(*r.end).ok());
  EXPECT_EQ(w.bytesWritten(), encoded.size());
  EXPECT_EQ(fileBytes(path), encoded);
  const Result<SessionRecording> read = readSessionFile(path);
  ASSERT_TRUE(read.ok()) << read.message();
  expectSameRecording(*read, r);
}

TEST(SessionFileTest, EachBudgetedStepAddsOneScheduleRecordOf32Bytes) {
  const std::vector<uint8_t> plain = encodeSession(testRecording());
  const std::vector<uint8_t> scheduled = encodeSession(scheduledRecording());
  EXPECT_EQ(scheduled.size(), plain.size() + 4 * kScheduleRecordBytes);  // four budgeted steps

  // Records: step 10, its schedule, step 11, params 1, step 12, its schedule, ...
  const std::vector<size_t> starts = recordStarts(scheduled);
  const size_t at = starts[1];
  ASSERT_EQ(starts[2] - at, kScheduleRecordBytes);
  EXPECT_EQ(scheduled[starts[0]], 1);
  EXPECT_EQ(scheduled[starts[2]], 1);
  std::vector<uint8_t> expected;
  putRecord(expected, 6, schedulePayload(10, 3, kAll, kAll));
  EXPECT_EQ(std::vector<uint8_t>(scheduled.begin() + std::ptrdiff_t(at), scheduled.begin() + std::ptrdiff_t(starts[2])),
            expected);

  // A recording of default schedules only is the file it was before schedules existed.
  EXPECT_EQ(recordStarts(plain).size(), starts.size() - 4);
}

// Step 5 and 6 as encodeSteps writes them, then `payload` as a schedule record.
std::vector<uint8_t> withSchedule(const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> bytes = encodeSteps({step(5), step(6)});
  putRecord(bytes, 6, payload);
  return bytes;
}

TEST(SessionFileTest, RefusesAScheduleThatDoesNotFollowItsStep) {
  // After step 6's record, a schedule for step 6 belongs; one for step 5 or 7 does not.
  ASSERT_TRUE(parse(withSchedule(schedulePayload(6, 1, 2, 3))).ok());
  std::vector<uint8_t> bytes = withSchedule(schedulePayload(5, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": schedule for step 5 does not follow step 5's record (it follows step 6's record)");
  bytes = withSchedule(schedulePayload(7, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": schedule for step 7 does not follow step 7's record (it follows step 6's record)");
  // Twice for one step.
  bytes = withSchedule(schedulePayload(6, 1, 2, 3));
  putRecord(bytes, 6, schedulePayload(6, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 4) +
                                ": schedule for step 6 does not follow step 6's record (it follows step 6's schedule)");
  // With another record between, or before any step.
  bytes = encodeSteps({step(5), step(6)});
  putRecord(bytes, 5, devicePayload(7, 0, "fault", ""));
  putRecord(bytes, 6, schedulePayload(6, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 4) +
                                ": schedule for step 6 does not follow step 6's record (it follows a device event at step 7)");
  bytes = encodeSteps({step(5), step(6)});
  putRecord(bytes, 2, paramsPayload(1, 7, "{}"));
  putRecord(bytes, 6, schedulePayload(6, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 4) +
                                ": schedule for step 6 does not follow step 6's record (it follows params serial 1)");
  bytes = encodeSteps({step(5)});
  putRecord(bytes, 3, gapPayload(6, 2));
  putRecord(bytes, 6, schedulePayload(5, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": schedule for step 5 does not follow step 5's record (it follows a gap from step 6)");
  bytes = headerOnly();
  putRecord(bytes, 6, schedulePayload(0, 1, 2, 3));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 1) +
                                ": schedule for step 0 does not follow step 0's record (it follows the header)");
}

TEST(SessionFileTest, RefusesASchedulePayloadOfTheWrongLength) {
  std::vector<uint8_t> payload = schedulePayload(6, 1, 2, 3);
  payload.resize(16);  // no cuts
  std::vector<uint8_t> bytes = withSchedule(payload);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) + ": schedule payload of 16 bytes, expected 20");
  payload = schedulePayload(6, 1, 2, 3);
  put<uint32_t>(payload, 4);  // a field this version does not know
  bytes = withSchedule(payload);
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) + ": schedule payload of 24 bytes, expected 20");
}

TEST(SessionFileTest, RefusesADefaultSchedule) {
  const std::vector<uint8_t> bytes = withSchedule(schedulePayload(6, kAll, kAll, kAll));
  expectError(parse(bytes), kWhere + ": " + recordAt(bytes, 3) +
                                ": schedule for step 6 is the default (every field 0xffffffff): a step that did all "
                                "its work has no schedule record");
}

// A crash inside a schedule record keeps every record before it, as anywhere else: its step reads
// back, but as a step that did all its work (docs/SESSIONS.md says what that means for a replay).
TEST(SessionFileTest, TruncationInsideAScheduleKeepsTheRecordsBeforeIt) {
  std::vector<SessionStep> steps = {step(5), step(6)};
  steps[0].schedule = schedule(1, 2, 3);
  steps[1].schedule = schedule(4, kAll, 0);
  const std::vector<uint8_t> bytes = encodeSteps(steps);
  const std::vector<size_t> starts = recordStarts(bytes);  // step 5, its schedule, step 6, its schedule, end of file
  ASSERT_EQ(starts.size(), 5u);
  ASSERT_EQ(starts[4] - starts[3], kScheduleRecordBytes);
  for (size_t cut = starts[3] + 1; cut < starts[4]; ++cut) {
    const std::vector<uint8_t> prefix(bytes.begin(), bytes.begin() + std::ptrdiff_t(cut));
    const Result<SessionRecording> r = parse(prefix);
    ASSERT_TRUE(r.ok()) << "cut at " << cut << ": " << r.message();
    EXPECT_EQ(r->truncation_warning, kWhere + ": cut off at byte " + std::to_string(cut) +
                                         " inside record 4 (which starts at byte " + std::to_string(starts[3]) +
                                         "); read 2 steps");
    ASSERT_EQ(r->steps.size(), 2u);
    expectSameStep(r->steps[0], steps[0]);
    SessionStep unscheduled = steps[1];
    unscheduled.schedule = {};
    expectSameStep(r->steps[1], unscheduled);
  }
  // The last record whole, its checksum damaged (a crash before its content reached the disk).
  std::vector<uint8_t> damaged = bytes;
  damaged[starts[3] + kFrameBytes + 9] ^= 0xff;
  const Result<SessionRecording> r = parse(damaged);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r->truncation_warning.empty());
  ASSERT_EQ(r->steps.size(), 2u);
  EXPECT_TRUE(r->steps[1].schedule.isDefault());
}

TEST(SessionFileTest, HeaderKeysAreAllRequiredAndNoneUnknown) {
  nlohmann::ordered_json h = headerJson();
  h.erase("task");
  expectError(parse(rawHeader(h.dump())), kWhere + ": header: missing key \"task\"");
  h = headerJson();
  h["tooth"].erase("voxel_mm");
  expectError(parse(rawHeader(h.dump())), kWhere + ": header: tooth: missing key \"voxel_mm\"");
  h = headerJson();
  h["colour"] = "blue";
  expectError(parse(rawHeader(h.dump())), kWhere + ": header: unknown key \"colour\"");
  h = headerJson();
  h["tools"]["handpiece"] = "x";
  expectError(parse(rawHeader(h.dump())), kWhere + ": header: tools: unknown key \"handpiece\"");

  // nlohmann would keep only the last of two equal keys; the reader refuses them.
  std::string text = headerJson().dump();
  text.insert(1, "\"task\":\"other\",");
  expectError(parse(rawHeader(text)), kWhere + ": header: duplicate key \"task\"");
  text = headerJson().dump();
  text.insert(text.find("\"hash\""), "\"level\":4,");
  expectError(parse(rawHeader(text)), kWhere + ": header: duplicate key tooth.\"level\"");

  // nlohmann prints a tree recursively, so a hostile header must not nest without bound.
  h = headerJson();
  h["params"]["deep"] = nlohmann::ordered_json::parse(std::string(100, '[') + std::string(100, ']'));
  expectError(parse(rawHeader(h.dump())), kWhere + ": header: nested deeper than 64 levels");
}

TEST(SessionFileTest, HeaderValuesAreChecked) {
  const auto expectHeaderError = [](const char* key, const char* sub, nlohmann::ordered_json value,
                                    const std::string& message) {
    nlohmann::ordered_json h = headerJson();
    (sub ? h[key][sub] : h[key]) = std::move(value);
    expectError(parse(rawHeader(h.dump())), kWhere + ": header: " + message);
  };
  expectHeaderError("format", nullptr, "dentsim-pen-path",
                    "format: expected \"dentsim-session\", found string \"dentsim-pen-path\"");
  expectHeaderError("version", nullptr, 2, "version: expected 1, found number 2");
  expectHeaderError("rate_hz", nullptr, "1000", "rate_hz: expected a number, found string \"1000\"");
  expectHeaderError("rate_hz", nullptr, 20000.0, "rate_hz: 20000 Hz is outside [100, 10000]");
  expectHeaderError("tooth", "hash", "0123456789ABCDEF", "tooth.hash: \"0123456789ABCDEF\" is not 16 lower-case hex digits");
  expectHeaderError("tooth", "level", 13, "tooth.level: expected an integer in [3, 12], found number 13");
  expectHeaderError("tooth", "level", 9.0, "tooth.level: expected an integer in [3, 12], found number 9.0");
  expectHeaderError("tooth", "voxel_mm", 0.0, "tooth.voxel_mm: 0 mm is not a finite size > 0");
  expectHeaderError("tools", "drill", "", "tools.drill: empty (the drill pen always carries a tool)");
  expectHeaderError("tools", "mirror", nullptr, "tools.mirror: expected a string, found null");
  expectHeaderError("params", nullptr, nlohmann::ordered_json::array({1, 2}),
                    "params: expected an object (the parameter set), found array");

  expectError(parse(rawHeader("{\"format\":")), kWhere + ": header: not valid JSON: parse error at line 1, column 11: "
                                                         "syntax error while parsing value - unexpected end of input; "
                                                         "expected '[', '{', or a literal");
  expectError(parse(rawHeader(headerJson().dump(), 2)),
              kWhere + ": unsupported session file version 2 (this dentsim reads 1)");
}

TEST(SessionFileTest, LimitsAreErrors) {
  const std::vector<uint8_t> bytes = encodeSession(testRecording());
  SessionReadLimits limits;
  limits.max_steps = 3;
  expectError(parse(bytes, limits), kWhere + ": " + recordAt(bytes, 5) + ": more than 3 steps, the limit for one session");

  limits = {};
  limits.max_header_bytes = 64;
  const Result<SessionRecording> header = parse(bytes, limits);
  ASSERT_FALSE(header.ok());
  EXPECT_NE(header.message().find("exceeds the limit of 64 bytes"), std::string::npos) << header.message();

  // A length over the limit is an error even when the file also ends inside that record.
  limits = {};
  limits.max_record_bytes = 100;
  std::vector<uint8_t> cut = encodeSteps({step(1)});  // both pens
  cut.resize(cut.size() - 5);
  expectError(parse(cut, limits), kWhere + ": " + recordAt(cut, 1) + ": payload of 309 bytes exceeds the limit of 100 bytes");
}

}  // namespace
}  // namespace dentsim
