// Tests of src/io/pen_path_file.cpp: bit-exact CSV and JSON round trips, hand-written files, every error class's one-line message, save and load.
#include "io/pen_path_file.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "test_support.h"

namespace dentsim {
namespace {

// ---- fixtures -------------------------------------------------------------------------------

PenSample sample(double t, PenRole pen, Vec3 position, Quat rotation = {}, uint32_t buttons = 0, double pedal = 0) {
  PenSample s;
  s.t_s = t;
  s.pen = pen;
  s.pose = {position, rotation};
  s.buttons = buttons;
  s.pedal = pedal;
  return s;
}

// Doubles that a careless writer loses: 0.1 (no short binary form), the smallest subnormal, -0.0,
// 1e-300, the largest double, a third, and an integer that to_chars writes without an exponent.
PenPath awkwardPath() {
  constexpr double kMax = std::numeric_limits<double>::max();
  constexpr double kTiny = std::numeric_limits<double>::denorm_min();
  const Quat tilted = Quat{0.1, 0.2, 0.3, 0.4}.normalized();  // components with long expansions
  PenPath p;
  p.samples = {
      sample(-0.0, PenRole::Drill, {0.1, -0.0, 1e-300}, Quat{-0.0, 0, 0, 1}, 0, -0.0),
      sample(kTiny, PenRole::Mirror, {kMax, -kMax, kTiny}, tilted, 0xffffffffu, kTiny),
      sample(1e-300, PenRole::Drill, {1.0 / 3.0, 123456789012345683968.0, -2.5}, Quat{0.5, -0.5, 0.5, -0.5}, 5, 1.0),
      sample(0.1, PenRole::Drill, {1e22, 4.9e-300, 17}, tilted.conjugate(), 1, 0.1),
      sample(1.0 / 3.0, PenRole::Mirror, {-1e-5, 2e5, 3}, {}, 2, 1.0 / 3.0),
  };
  return p;
}

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

// Equal bit for bit: -0.0 differs from 0.0 here, unlike with ==.
void expectSameBits(const PenPath& a, const PenPath& b) {
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (size_t i = 0; i < a.samples.size(); ++i) {
    const PenSample& x = a.samples[i];
    const PenSample& y = b.samples[i];
    EXPECT_EQ(bits(x.t_s), bits(y.t_s)) << "sample " << i;
    EXPECT_EQ(x.pen, y.pen) << "sample " << i;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(x.pose.position[k]), bits(y.pose.position[k])) << "sample " << i;
    EXPECT_EQ(bits(x.pose.rotation.w), bits(y.pose.rotation.w)) << "sample " << i;
    EXPECT_EQ(bits(x.pose.rotation.x), bits(y.pose.rotation.x)) << "sample " << i;
    EXPECT_EQ(bits(x.pose.rotation.y), bits(y.pose.rotation.y)) << "sample " << i;
    EXPECT_EQ(bits(x.pose.rotation.z), bits(y.pose.rotation.z)) << "sample " << i;
    EXPECT_EQ(x.buttons, y.buttons) << "sample " << i;
    EXPECT_EQ(bits(x.pedal), bits(y.pedal)) << "sample " << i;
  }
}

Result<PenPath> csv(const std::string& text, const PenPathReadLimits& limits = {}) {
  return parsePenPathCsv(text, "p.csv", limits);
}
Result<PenPath> json(const std::string& text, const PenPathReadLimits& limits = {}) {
  return parsePenPathJson(text, "p.json", limits);
}

// The whole message, which must be one line.
void expectError(const Result<PenPath>& r, const std::string& message) {
  ASSERT_FALSE(r.ok()) << "expected: " << message;
  EXPECT_EQ(r.message(), message);
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\r'), std::string::npos) << r.message();
}

const std::string kHeader = std::string(kPenPathCsvHeader) + "\n";
// A valid row for time t of the given pen.
std::string row(const std::string& t, const std::string& pen = "drill") { return t + "," + pen + ",0,0,0,1,0,0,0,0,0\n"; }

// The JSON file around `samples` (the text between the brackets).
std::string jsonFile(const std::string& samples) {
  return R"({"format":"dentsim-pen-path","version":1,"samples":[)" + samples + "]}";
}
// One JSON sample with a field replaced: `field` names it, `value` is its JSON text ("" drops it).
std::string jsonSample(const std::string& field = "", const std::string& value = "") {
  const std::vector<std::pair<std::string, std::string>> fields = {
      {"t_s", "0.5"}, {"pen", "\"drill\""}, {"position_mm", "[1,2,3]"}, {"rotation_wxyz", "[1,0,0,0]"},
      {"buttons", "0"}, {"pedal", "0"}};
  std::string out = "{";
  for (const auto& [name, text] : fields) {
    const std::string v = name == field ? value : text;
    if (v.empty()) continue;
    out += (out.size() > 1 ? "," : "") + ("\"" + name + "\":" + v);
  }
  return out + "}";
}

// ---- round trips ----------------------------------------------------------------------------

TEST(PenPathFileTest, CsvRoundTripIsBitExact) {
  const PenPath path = awkwardPath();
  ASSERT_TRUE(checkPenPath(path, "awkward").ok()) << checkPenPath(path, "awkward").message();
  const Result<PenPath> back = csv(penPathCsv(path));
  ASSERT_TRUE(back.ok()) << back.message();
  expectSameBits(*back, path);
  // Writing what was read gives the same text again.
  EXPECT_EQ(penPathCsv(*back), penPathCsv(path));
}

TEST(PenPathFileTest, JsonRoundTripIsBitExact) {
  const PenPath path = awkwardPath();
  const std::string text = penPathJson(path);
  // -0.0 must not be written as the integer -0, which JSON readers take as 0.
  EXPECT_NE(text.find("\"t_s\":-0.0,"), std::string::npos) << text;
  const Result<PenPath> back = json(text);
  ASSERT_TRUE(back.ok()) << back.message();
  expectSameBits(*back, path);
  EXPECT_EQ(penPathJson(*back), text);
}

TEST(PenPathFileTest, CsvTextLooksAsDocumented) {
  PenPath path;
  path.samples = {sample(0.25, PenRole::Mirror, {1, -2.5, 0.1}, {}, 3, 0.5)};
  EXPECT_EQ(penPathCsv(path), kHeader + "0.25,mirror,1,-2.5,0.1,1,0,0,0,3,0.5\n");
  EXPECT_EQ(penPathJson(path),
            "{\"format\":\"dentsim-pen-path\",\"version\":1,\"samples\":[\n"
            "{\"t_s\":0.25,\"pen\":\"mirror\",\"position_mm\":[1.0,-2.5,0.1],\"rotation_wxyz\":[1.0,0.0,0.0,0.0],"
            "\"buttons\":3,\"pedal\":0.5}\n]}\n");
}

// ---- hand-written files ---------------------------------------------------------------------

TEST(PenPathFileTest, HandWrittenCsvParses) {
  // Comments and blank lines anywhere, CRLF line ends, blanks around fields, a '+' sign, and the
  // mirror's sample at 0.1 s written after the drill's at 0.2 s: the path comes back sorted by time.
  const std::string text =
      "# a scripted approach to the occlusal surface\r\n"
      "\n" +
      std::string(kPenPathCsvHeader) + "\r\n" +
      "0,drill,10,20,30,1,0,0,0,0,0\r\n"
      "   \t\r\n"
      "  # drill runs up\n"
      "0.2, drill ,10,20,29.5,+0.7071067811865476,0.7071067811865476,0,0,1,0.75\n"
      "0.1,mirror,-5,0,12,0,0,1,0,4294967295,1\n"
      "0.2,mirror,-5,0,12.5,0,0,1,0,0,1";  // no newline at the end
  const Result<PenPath> r = csv(text);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->samples.size(), 4u);
  const auto& s = r->samples;
  EXPECT_EQ(s[0], sample(0, PenRole::Drill, {10, 20, 30}));
  EXPECT_EQ(s[1], sample(0.1, PenRole::Mirror, {-5, 0, 12}, Quat{0, 0, 1, 0}, 0xffffffffu, 1));
  // The two samples at 0.2 s keep their file order.
  EXPECT_EQ(s[2].pen, PenRole::Drill);
  EXPECT_EQ(s[2].t_s, 0.2);
  EXPECT_EQ(s[2].pose.position, (Vec3{10, 20, 29.5}));
  EXPECT_NEAR(s[2].pose.rotation.w, std::sqrt(0.5), 1e-16);
  EXPECT_NEAR(s[2].pose.rotation.x, std::sqrt(0.5), 1e-16);
  EXPECT_EQ(s[2].buttons, 1u);
  EXPECT_EQ(s[2].pedal, 0.75);
  EXPECT_EQ(s[3], sample(0.2, PenRole::Mirror, {-5, 0, 12.5}, Quat{0, 0, 1, 0}, 0, 1));
}

TEST(PenPathFileTest, HandWrittenJsonParses) {
  // Keys in any order and whitespace anywhere; integers are numbers too.
  const std::string text = R"({
    "samples": [
      {"pen": "drill", "t_s": 0, "position_mm": [10, 20, 30], "rotation_wxyz": [1, 0, 0, 0],
       "buttons": 0, "pedal": 0},
      {"t_s": 0.5, "pen": "mirror", "position_mm": [-5, 0, 12.5], "rotation_wxyz": [0, 0, 1, 0],
       "buttons": 4294967295, "pedal": 1.0},
      {"t_s": 0.25, "pen": "drill", "position_mm": [10, 20, 29.5e0], "rotation_wxyz": [0, 1, 0, 0],
       "buttons": 2, "pedal": 0.75}
    ],
    "version": 1,
    "format": "dentsim-pen-path"
  })";
  const Result<PenPath> r = json(text);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->samples.size(), 3u);
  EXPECT_EQ(r->samples[0], sample(0, PenRole::Drill, {10, 20, 30}));
  EXPECT_EQ(r->samples[1], sample(0.25, PenRole::Drill, {10, 20, 29.5}, Quat{0, 1, 0, 0}, 2, 0.75));
  EXPECT_EQ(r->samples[2], sample(0.5, PenRole::Mirror, {-5, 0, 12.5}, Quat{0, 0, 1, 0}, 0xffffffffu, 1));
}

TEST(PenPathFileTest, NearlyUnitRotationsAreNormalised) {
  // Norm 1.0005 is within the 1e-3 tolerance: the rotation comes back divided by it.
  const Result<PenPath> r = csv(kHeader + "0,drill,0,0,0,0.6003,0.8004,0,0,0,0\n");
  ASSERT_TRUE(r.ok()) << r.message();
  const Quat& q = r->samples[0].pose.rotation;
  EXPECT_NEAR(q.w, 0.6, 1e-15);
  EXPECT_NEAR(q.x, 0.8, 1e-15);
  EXPECT_NEAR(std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z), 1.0, 1e-15);
  // Reading again what was written changes nothing.
  const Result<PenPath> again = csv(penPathCsv(*r));
  ASSERT_TRUE(again.ok()) << again.message();
  expectSameBits(*again, *r);
}

TEST(PenPathFileTest, EqualTimesAndBothPensAreAccepted) {
  const Result<PenPath> r = csv(kHeader + row("1") + row("1") + row("0.5", "mirror") + row("1", "mirror"));
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->samples.size(), 4u);
  EXPECT_EQ(r->samples[0].pen, PenRole::Mirror);
  EXPECT_EQ(r->samples[0].t_s, 0.5);
}

// ---- CSV errors -----------------------------------------------------------------------------

TEST(PenPathFileTest, CsvHeaderAndShapeErrors) {
  expectError(csv(""), "p.csv: no samples (no header line)");
  expectError(csv("# only a comment\n\n"), "p.csv: no samples (no header line)");
  expectError(csv(kHeader), "p.csv: no samples");
  expectError(csv("# recorded\nt_s,pen,x,y,z,qw,qx,qy,qz,buttons,pedal\n" + row("0")),
              "p.csv:2: expected the header \"t_s,pen,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,pedal\", found "
              "\"t_s,pen,x,y,z,qw,qx,qy,qz,buttons,pedal\"");
  // A data row where the header should be.
  expectError(csv(row("0")), "p.csv:1: expected the header \"t_s,pen,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,pedal\", "
                             "found \"0,drill,0,0,0,1,0,0,0,0,0\"");
  expectError(csv(kHeader + row("0") + "\n0.1,drill,0,0,0,1,0,0,0,0\n"),
              "p.csv:4: expected 11 comma-separated columns, found 10");
  expectError(csv(kHeader + "0.1,drill,0,0,0,1,0,0,0,0,0,\n"), "p.csv:2: expected 11 comma-separated columns, found 12");
}

TEST(PenPathFileTest, CsvNumberErrors) {
  expectError(csv(kHeader + "0.1x,drill,0,0,0,1,0,0,0,0,0\n"), "p.csv:2: t_s: expected a number, found \"0.1x\"");
  expectError(csv(kHeader + "0,drill,0,,0,1,0,0,0,0,0\n"), "p.csv:2: y_mm: expected a number, found \"\"");
  expectError(csv(kHeader + "0,drill,0,0,1 2,1,0,0,0,0,0\n"), "p.csv:2: z_mm: expected a number, found \"1 2\"");
  expectError(csv(kHeader + "0,drill,0,0,0,0x1,0,0,0,0,0\n"), "p.csv:2: qw: expected a number, found \"0x1\"");
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0,0,1,5\n"), "p.csv:2: expected 11 comma-separated columns, found 12");
  expectError(csv(kHeader + "0,drill,1e400,0,0,1,0,0,0,0,0\n"),
              "p.csv:2: x_mm: number \"1e400\" is out of the double range");
  // Control bytes are shown escaped, so that the message stays one line.
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0,0,\x01\n"), "p.csv:2: pedal: expected a number, found \"\\x01\"");
}

TEST(PenPathFileTest, CsvNonFiniteValuesAreRefused) {
  expectError(csv(kHeader + "nan,drill,0,0,0,1,0,0,0,0,0\n"), "p.csv:2: t_s: not finite (nan)");
  expectError(csv(kHeader + row("0") + "1,drill,0,inf,0,1,0,0,0,0,0\n"), "p.csv:3: y_mm: not finite (inf)");
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,-infinity,0,0,0\n"), "p.csv:2: qy: not finite (-inf)");
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0,0,NaN\n"), "p.csv:2: pedal: not finite (nan)");
}

TEST(PenPathFileTest, CsvValueErrors) {
  expectError(csv(kHeader + row("-0.5")), "p.csv:2: t_s: negative time -0.5 s");
  // The drill goes back in time on line 4; the mirror's earlier sample on line 3 is fine.
  expectError(csv(kHeader + row("1") + row("0.5", "mirror") + row("0.75")),
              "p.csv:4: t_s: time 0.75 s is earlier than the previous drill sample's 1 s");
  expectError(csv(kHeader + "0,drill,0,0,0,0.5,0,0,0,0,0\n"),
              "p.csv:2: rotation: norm 0.5 is not within 0.001 of 1 (not a unit quaternion)");
  expectError(csv(kHeader + "0,drill,0,0,0,1.002,0,0,0,0,0\n"),
              "p.csv:2: rotation: norm 1.002 is not within 0.001 of 1 (not a unit quaternion)");
  expectError(csv(kHeader + "0,drill,0,0,0,0,0,0,0,0,0\n"),
              "p.csv:2: rotation: norm 0 is not within 0.001 of 1 (not a unit quaternion)");
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0,0,1.5\n"), "p.csv:2: pedal: 1.5 is outside [0, 1]");
  expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0,0,-0.1\n"), "p.csv:2: pedal: -0.1 is outside [0, 1]");
  expectError(csv(kHeader + "0,pencil,0,0,0,1,0,0,0,0,0\n"),
              "p.csv:2: pen: expected \"drill\" or \"mirror\", found \"pencil\"");
  expectError(csv(kHeader + "0,Drill,0,0,0,1,0,0,0,0,0\n"),
              "p.csv:2: pen: expected \"drill\" or \"mirror\", found \"Drill\"");
  for (const char* buttons : {"-1", "4294967296", "1.0", "+1", "0x1", "", "99999999999999999999999"})
    expectError(csv(kHeader + "0,drill,0,0,0,1,0,0,0," + buttons + ",0\n"),
                "p.csv:2: buttons: expected an integer in [0, 4294967295], found \"" + std::string(buttons) + "\"");
}

TEST(PenPathFileTest, CsvSampleLimit) {
  PenPathReadLimits limits;
  limits.max_samples = 2;
  EXPECT_TRUE(csv(kHeader + row("0") + row("1"), limits).ok());
  expectError(csv(kHeader + row("0") + "# c\n" + row("1") + row("2"), limits),
              "p.csv:5: more than 2 samples, the limit for one path");
}

// ---- JSON errors ----------------------------------------------------------------------------

TEST(PenPathFileTest, JsonDocumentErrors) {
  expectError(json(""), "p.json: not valid JSON: parse error at line 1, column 1: syntax error while parsing value - "
                        "unexpected end of input; expected '[', '{', or a literal");
  expectError(json("[]"), "p.json: expected a JSON object (a pen path), found an array");
  expectError(json(R"({"format":"dentsim-scene","version":1,"samples":[]})"),
              "p.json: format: expected \"dentsim-pen-path\", found the string \"dentsim-scene\"");
  expectError(json(R"({"format":"dentsim-pen-path","version":2,"samples":[]})"),
              "p.json: version: unsupported version \"2\" (this reader knows version 1)");
  expectError(json(R"({"format":"dentsim-pen-path","version":1.0,"samples":[]})"),
              "p.json: version: unsupported version \"1.0\" (this reader knows version 1)");
  expectError(json(R"({"format":"dentsim-pen-path","version":"1","samples":[]})"),
              "p.json: version: expected a number, found the string \"1\"");
  expectError(json(R"({"format":"dentsim-pen-path","version":1,"samples":[],"units":"mm"})"),
              "p.json: unknown key \"units\"");
  expectError(json(R"({"format":"dentsim-pen-path","format":"dentsim-pen-path"})"), "p.json: format: duplicate key");
  expectError(json(R"({"format":"dentsim-pen-path","samples":[]})"), "p.json: missing key \"version\"");
  expectError(json(jsonFile("")), "p.json: no samples");
  expectError(json(R"({"format":"dentsim-pen-path","version":1,"samples":{}})"),
              "p.json: samples: expected an array of samples, found an object");
  expectError(json(jsonFile(jsonSample()) + " x"),
              "p.json: not valid JSON: parse error at line 1, column 151: syntax error while parsing value - "
              "invalid literal; last read: '0}]} x'; expected end of input");
  // Control bytes in what the parser quotes are escaped, so that the message stays one line.
  expectError(json("{\"format\":\"a\nb\"}"),
              "p.json: not valid JSON: parse error at line 2, column 0: syntax error while parsing value - "
              "invalid string: control character U+000A (LF) must be escaped to \\u000A or \\n; last read: "
              "'\"a<U+000A>'");
}

TEST(PenPathFileTest, JsonSampleErrors) {
  const std::string ok = jsonSample() + ",";
  expectError(json(jsonFile(ok + "[]")), "p.json: samples[1]: expected an object, found an array");
  expectError(json(jsonFile(ok + jsonSample("pedal", "0,\"speed\":3"))), "p.json: samples[1]: unknown key \"speed\"");
  expectError(json(jsonFile(jsonSample("pen", "\"drill\",\"pen\":\"drill\""))), "p.json: samples[0].pen: duplicate key");
  expectError(json(jsonFile(ok + jsonSample("pedal", ""))), "p.json: samples[1].pedal: missing");
  expectError(json(jsonFile(jsonSample("t_s", "\"0.5\""))),
              "p.json: samples[0].t_s: expected a number, found the string \"0.5\"");
  expectError(json(jsonFile(jsonSample("t_s", "null"))), "p.json: samples[0].t_s: expected a number, found null");
  // A number beyond the double range stops the JSON parser itself.
  expectError(json(jsonFile(jsonSample("t_s", "1e400"))),
              "p.json: number overflow parsing '1e400' (beyond the double range) near byte 64");
  expectError(json(jsonFile(jsonSample("t_s", "-1"))), "p.json: samples[0].t_s: negative time -1 s");
  expectError(json(jsonFile(jsonSample("pen", "\"scaler\""))),
              "p.json: samples[0].pen: expected \"drill\" or \"mirror\", found the string \"scaler\"");
  expectError(json(jsonFile(jsonSample("pen", "0"))),
              "p.json: samples[0].pen: expected \"drill\" or \"mirror\", found the number \"0\"");
  expectError(json(jsonFile(jsonSample("position_mm", "[1,2]"))),
              "p.json: samples[0].position_mm: expected 3 numbers, found 2");
  expectError(json(jsonFile(jsonSample("position_mm", "[1,2,3,4]"))),
              "p.json: samples[0].position_mm: expected 3 numbers, found more");
  expectError(json(jsonFile(jsonSample("position_mm", "[1,[2],3]"))),
              "p.json: samples[0].position_mm[1]: expected a number, found an array");
  expectError(json(jsonFile(jsonSample("position_mm", "{}"))),
              "p.json: samples[0].position_mm: expected an array of 3 numbers, found an object");
  expectError(json(jsonFile(jsonSample("rotation_wxyz", "[1,0,0]"))),
              "p.json: samples[0].rotation_wxyz: expected 4 numbers, found 3");
  expectError(json(jsonFile(jsonSample("rotation_wxyz", "[0.9,0,0,0]"))),
              "p.json: samples[0].rotation_wxyz: norm 0.9 is not within 0.001 of 1 (not a unit quaternion)");
  for (const char* buttons : {"-1", "4294967296", "1.0", "true", "\"1\""})
    expectError(json(jsonFile(jsonSample("buttons", buttons))),
                "p.json: samples[0].buttons: expected an integer in [0, 4294967295], found " +
                    std::string(buttons[0] == 't' ? "a boolean"
                                : buttons[0] == '"' ? "the string \"1\""
                                                    : "the number \"" + std::string(buttons) + "\""));
  expectError(json(jsonFile(jsonSample("pedal", "1.25"))), "p.json: samples[0].pedal: 1.25 is outside [0, 1]");
  expectError(json(jsonFile(jsonSample("t_s", "2") + "," + jsonSample("t_s", "1"))),
              "p.json: samples[1].t_s: time 1 s is earlier than the previous drill sample's 2 s");
}

TEST(PenPathFileTest, JsonSampleLimit) {
  PenPathReadLimits limits;
  limits.max_samples = 1;
  EXPECT_TRUE(json(jsonFile(jsonSample()), limits).ok());
  expectError(json(jsonFile(jsonSample() + "," + jsonSample()), limits),
              "p.json: samples: more than 1 samples, the limit for one path");
}

// ---- checks, saving and loading -------------------------------------------------------------

TEST(PenPathFileTest, CheckRefusesWhatReadersWouldRefuse) {
  PenPath path = awkwardPath();
  EXPECT_TRUE(checkPenPath(path, "x").ok());
  path.samples[1].pose.position.y = std::nan("");
  EXPECT_EQ(checkPenPath(path, "x").message(), "x: samples[1].position_mm[1]: not finite (nan)");
  path = awkwardPath();
  // The mirror at 1/3 s, then the drill at 0.1 s: each pen is in order, the path is not.
  std::swap(path.samples[3], path.samples[4]);
  EXPECT_EQ(checkPenPath(path, "x").message(),
            "x: samples[4].t_s: time 0.1 s is earlier than samples[3]'s 0.3333333333333333 s (samples must be "
            "sorted by time)");
  path.samples.clear();
  EXPECT_EQ(checkPenPath(path, "x").message(), "x: no samples");
}

TEST(PenPathFileTest, SaveAndLoadBothEncodings) {
  const test::TempDir dir;
  const PenPath path = awkwardPath();
  for (const char* name : {"path.csv", "path.json", "PATH.JSON"}) {
    const std::string file = dir.file(name);
    ASSERT_TRUE(savePenPath(file, path).ok()) << name;
    const Result<PenPath> back = loadPenPath(file);
    ASSERT_TRUE(back.ok()) << back.message();
    expectSameBits(*back, path);
  }
  // The extension picked the encoding.
  std::ifstream in(dir.file("path.json"));
  EXPECT_EQ(in.get(), '{');
  // Any other name: saved as CSV, and read by sniffing the first byte.
  const std::string other = dir.file("path.txt");
  ASSERT_TRUE(savePenPath(other, path).ok());
  ASSERT_TRUE(loadPenPath(other).ok());
  {
    std::ofstream out(dir.file("json.txt"));
    out << "\n  " << penPathJson(path);
  }
  const Result<PenPath> sniffed = loadPenPath(dir.file("json.txt"));
  ASSERT_TRUE(sniffed.ok()) << sniffed.message();
  expectSameBits(*sniffed, path);
}

TEST(PenPathFileTest, SaveRefusesAnInvalidPath) {
  const test::TempDir dir;
  PenPath path = awkwardPath();
  path.samples[0].pedal = 2;
  const std::string file = dir.file("bad.csv");
  const Status s = savePenPath(file, path);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), file + ": samples[0].pedal: 2 is outside [0, 1]");
  EXPECT_FALSE(std::filesystem::exists(file));
}

TEST(PenPathFileTest, LoadErrorsNameThePath) {
  const test::TempDir dir;
  const std::string missing = dir.file("missing.csv");
  const Result<PenPath> r = loadPenPath(missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(missing + ": ", 0), 0u) << r.message();
  // A parse error names the file too, with the CSV line.
  const std::string bad = dir.file("bad.csv");
  {
    std::ofstream out(bad);
    out << kHeader << row("0") << "1,drill\n";
  }
  expectError(loadPenPath(bad), bad + ":3: expected 11 comma-separated columns, found 2");
}

}  // namespace
}  // namespace dentsim
