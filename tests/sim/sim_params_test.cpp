// Tests of SimParams presets: defaults, the JSON round trip, the checked-in default, partial presets, one-line errors, save/load and fuzzing.
#include "sim/sim_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "model/builtin_assets.h"
#include "model/tool_generator.h"

#include "fuzz_mutations.h"
#include "test_support.h"

namespace dentsim {
namespace {

const std::string kWhere = "t.json";

// A preset holding `body` after the format and version lines.
std::string preset(const std::string& body) {
  return std::string(R"({"format": "dentsim-params", "version": 1)") + (body.empty() ? "" : ", " + body) + "}";
}

// True when both doubles have the same bits (so 0 and -0 differ, unlike ==).
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// ---- defaults ----------------------------------------------------------------------------------------

TEST(SimParams, DefaultsHoldThePapersHardness) {
  const SimParams p = defaultSimParams();
  EXPECT_EQ(p.tissue(Material::Enamel).hardness, 0.1);
  EXPECT_EQ(p.tissue(Material::Dentin).hardness, 0.1);
  EXPECT_EQ(p.tissue(Material::Pulp).hardness, 1.0);
  EXPECT_EQ(p.tissue(Material::Caries).hardness, 0.5);
  EXPECT_EQ(p.tissue(Material::Enamel).stiffness_n_per_mm3, 2000.0);
  EXPECT_EQ(p.tissue(Material::Caries).damping_s_per_mm, 0.004);
  // Empty and the spare codes 6..7 stay zero: nothing to touch there. A neighbour feels as enamel.
  EXPECT_EQ(p.tissue(Material::Neighbour), p.tissue(Material::Enamel));
  for (uint32_t m : {0u, 6u, 7u}) EXPECT_EQ(p.tissues[m], TissueParams{}) << "material " << m;
}

TEST(SimParams, DefaultsGiveEveryBuiltinBurAnAbility) {
  const SimParams p = defaultSimParams();
  size_t burs = 0;
  for (const ToolSpec& t : toolCatalog()) {
    switch (t.kind) {
      case ToolKind::RoundBur: EXPECT_EQ(p.cuttingAbility(t.name), 0.8) << t.name; ++burs; break;
      case ToolKind::FissureBur: EXPECT_EQ(p.cuttingAbility(t.name), 0.9) << t.name; ++burs; break;
      case ToolKind::ChamferBur:
      case ToolKind::ShoulderBur: EXPECT_EQ(p.cuttingAbility(t.name), 0.8) << t.name; ++burs; break;
      default: EXPECT_EQ(p.burs.count(t.name), 0u) << t.name << " is not a bur"; break;
    }
  }
  EXPECT_EQ(p.burs.size(), burs);
  EXPECT_EQ(p.cuttingAbility("no_such_bur"), 0.0);
}

// ---- JSON round trip ---------------------------------------------------------------------------------

TEST(SimParams, DefaultRoundTripsThroughJson) {
  const SimParams p = defaultSimParams();
  const std::string text = simParamsJson(p);
  auto back = parseSimParams(text, kWhere);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == p);
  EXPECT_EQ(simParamsJson(*back), text);
}

TEST(SimParams, AwkwardValuesRoundTripBitIdentical) {
  SimParams p = defaultSimParams();
  p.tissue(Material::Enamel).hardness = 0.1 + 0.2;                            // 0.30000000000000004
  p.tissue(Material::Dentin).stiffness_n_per_mm3 = 1.0 / 3.0;
  p.tissue(Material::Pulp).damping_s_per_mm = std::numeric_limits<double>::denorm_min();
  p.tissue(Material::Caries).friction = std::nextafter(2.0, 0.0);
  p.cutting.removal_rate_mm3_per_s = std::numeric_limits<double>::max();
  p.coupling.rot_damping_n_mm_s_per_rad = -0.0;                              // >= 0 holds for -0
  p.device.rate_hz = 1000.0 + 1e-10;
  p.burs["custom-bur.1"].cutting_ability = 1.0 / 7.0;
  auto back = parseSimParams(simParamsJson(p), kWhere);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == p);
  EXPECT_TRUE(sameBits(back->tissue(Material::Enamel).hardness, 0.1 + 0.2));
  EXPECT_TRUE(sameBits(back->tissue(Material::Dentin).stiffness_n_per_mm3, 1.0 / 3.0));
  EXPECT_TRUE(sameBits(back->tissue(Material::Pulp).damping_s_per_mm, std::numeric_limits<double>::denorm_min()));
  EXPECT_TRUE(sameBits(back->cutting.removal_rate_mm3_per_s, std::numeric_limits<double>::max()));
  EXPECT_TRUE(sameBits(back->coupling.rot_damping_n_mm_s_per_rad, -0.0));
  EXPECT_TRUE(sameBits(back->burs.at("custom-bur.1").cutting_ability, 1.0 / 7.0));
}

TEST(SimParams, JsonHasTheFixedLayout) {
  const std::string text = simParamsJson(defaultSimParams());
  // Sections in the fixed order, 2-space indent, one trailing newline.
  const char* sections[] = {"\"format\"", "\"version\"", "\"tissues\"", "\"burs\"", "\"turbine\"",
                            "\"cutting\"", "\"coupling\"", "\"device\"", "\"point_shell\""};
  size_t at = 0;
  for (const char* s : sections) {
    const size_t found = text.find(std::string("\n  ") + s, at);
    ASSERT_NE(found, std::string::npos) << s;
    at = found;
  }
  EXPECT_EQ(text.rfind("{\n  \"format\": \"dentsim-params\",\n  \"version\": 1,\n", 0), 0u);
  EXPECT_NE(text.find("\"enamel\": {\n      \"stiffness_n_per_mm3\": 2000.0,"), std::string::npos);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text[text.size() - 2], '\n');
}

// The checked-in assets/presets/default.json (as embedded) reads as the defaults. That the file is
// exactly what the code writes, looks included, is tests/ui/preset_test.cpp's check.
TEST(SimParams, CheckedInDefaultPresetEqualsDefaults) {
  const std::span<const uint8_t> embedded = builtinAssetBytes("presets/default.json");
  ASSERT_FALSE(embedded.empty()) << "assets/presets/default.json is not embedded";
  const std::string text(embedded.begin(), embedded.end());
  auto p = parseSimParams(text, "presets/default.json");
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_TRUE(*p == defaultSimParams());
}

// ---- partial presets ---------------------------------------------------------------------------------

TEST(SimParams, FormatAndVersionAloneGiveTheDefaults) {
  auto p = parseSimParams(preset(""), kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_TRUE(*p == defaultSimParams());
}

TEST(SimParams, PartialPresetOverridesOnlyWhatItNames) {
  auto p = parseSimParams(preset(R"(
      "tissues": {"enamel": {"hardness": 0.3}, "caries": {}},
      "burs": {"round_bur_010": {"cutting_ability": 0.5}, "diamond_flame": {"cutting_ability": 0.7}},
      "device": {"max_force_n": 3}
  )"), kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  SimParams expected = defaultSimParams();
  expected.tissue(Material::Enamel).hardness = 0.3;  // the enamel's other fields stay
  expected.burs["round_bur_010"].cutting_ability = 0.5;
  expected.burs["diamond_flame"].cutting_ability = 0.7;  // a new bur joins the built-in ones
  expected.device.max_force_n = 3.0;                    // an integer reads as a double
  EXPECT_TRUE(*p == expected);
  EXPECT_EQ(p->burs.size(), defaultSimParams().burs.size() + 1);
  EXPECT_EQ(p->tissue(Material::Enamel).stiffness_n_per_mm3, 2000.0);
}

// ---- errors ------------------------------------------------------------------------------------------

struct ErrorCase {
  const char* what;      // the class of error
  std::string text;      // the preset
  std::string expected;  // a substring of the message, after "t.json: "
};

std::vector<ErrorCase> errorCases() {
  return {
      {"syntax", "{\"format\": \"dentsim-params\",\n  \"version\": 1,,\n}",
       "invalid JSON: parse error at line 2, column 16: syntax error while parsing object key - unexpected ','"},
      {"truncated", preset("").substr(0, 20), "invalid JSON: parse error at line 1, column 21"},
      {"empty", "", "invalid JSON: parse error at line 1, column 1"},
      {"not an object", "[1, 2]", "(top level): expected an object, got array"},
      {"format missing", R"({"version": 1})", "format: missing"},
      {"format wrong", R"({"format": "dentsim-session", "version": 1})",
       R"(format: "dentsim-session" is not "dentsim-params")"},
      {"format far off", R"({"format": ")" + std::string(100, 'x') + R"(", "version": 1})",
       "format: \"" + std::string(64, 'x') + "\"... is not \"dentsim-params\""},
      {"format not a string", R"({"format": 7, "version": 1})", "format: expected a string, got number"},
      {"version missing", R"({"format": "dentsim-params"})", "version: missing"},
      {"version unsupported", R"({"format": "dentsim-params", "version": 2})",
       "version: 2 is not supported (this build reads version 1)"},
      {"version negative", R"({"format": "dentsim-params", "version": -1})", "version: -1 is not supported"},
      {"version a string", R"({"format": "dentsim-params", "version": "1"})", "version: expected an integer, got string"},
      {"version a float", R"({"format": "dentsim-params", "version": 1.0})", "version: expected an integer, got number"},
      {"unknown top key", preset(R"("colour": 1)"), "colour: unknown key (known: format, version, tissues, burs, "},
      {"unknown tissue", preset(R"("tissues": {"enamal": {}})"),
       "tissues.enamal: unknown key (known: enamel, dentin, pulp, caries, neighbour)"},
      {"empty is no tissue", preset(R"("tissues": {"empty": {}})"), "tissues.empty: unknown key"},
      {"unknown field", preset(R"("tissues": {"enamel": {"hardnes": 0.2}})"),
       "tissues.enamel.hardnes: unknown key (known: stiffness_n_per_mm3, damping_s_per_mm, friction, hardness)"},
      {"unknown bur field", preset(R"("burs": {"round_bur_010": {"speed": 1}})"),
       "burs.round_bur_010.speed: unknown key (known: cutting_ability)"},
      {"odd key stays on one line", preset("\"tissues\": {\"a\\nb\": {}}"), R"(tissues."a\nb": unknown key)"},
      {"repeated key", preset(R"("tissues": {"enamel": {"hardness": 0.2, "hardness": 0.3}})"),
       "tissues.enamel.hardness: repeated key"},
      {"repeated section", preset(R"("device": {}, "device": {})"), "device: repeated key"},
      {"number as string", preset(R"("tissues": {"enamel": {"hardness": "0.1"}})"),
       "tissues.enamel.hardness: expected a number, got string"},
      {"boolean", preset(R"("turbine": {"max_rpm": true})"), "turbine.max_rpm: expected a number, got boolean"},
      {"null", preset(R"("cutting": {"reach_mm": null})"), "cutting.reach_mm: expected a number, got null"},
      {"section not an object", preset(R"("device": [])"), "device: expected an object, got array"},
      {"tissue not an object", preset(R"("tissues": {"pulp": 3})"), "tissues.pulp: expected an object, got number"},
      {"burs not an object", preset(R"("burs": "round_bur_010")"), "burs: expected an object, got string"},
      {"bad bur name", preset(R"("burs": {"my bur": {"cutting_ability": 0.5}})"), R"(burs."my bur": not a tool name)"},
      {"empty bur name", preset(R"("burs": {"": {}})"), R"(burs."": not a tool name)"},
      {"overflow", preset(R"("tissues": {"enamel": {"stiffness_n_per_mm3": 1e999}})"),
       "tissues.enamel.stiffness_n_per_mm3: not a finite number"},
      {"negative overflow", preset(R"("device": {"rate_hz": -1e400})"), "device.rate_hz: not a finite number"},
      {"hardness", preset(R"("tissues": {"enamel": {"hardness": 1.5}})"), "tissues.enamel.hardness: 1.5 is not in [0, 1]"},
      {"hardness < 0", preset(R"("tissues": {"dentin": {"hardness": -0.1}})"), "tissues.dentin.hardness: -0.1 is not in [0, 1]"},
      {"stiffness 0", preset(R"("tissues": {"pulp": {"stiffness_n_per_mm3": 0}})"),
       "tissues.pulp.stiffness_n_per_mm3: 0 is not > 0"},
      {"damping < 0", preset(R"("tissues": {"caries": {"damping_s_per_mm": -0.5}})"),
       "tissues.caries.damping_s_per_mm: -0.5 is not >= 0"},
      {"friction > 2", preset(R"("tissues": {"enamel": {"friction": 2.5}})"), "tissues.enamel.friction: 2.5 is not in [0, 2]"},
      {"ability", preset(R"("burs": {"round_bur_008": {"cutting_ability": 1.1}})"),
       "burs.round_bur_008.cutting_ability: 1.1 is not in [0, 1]"},
      {"rpm 0", preset(R"("turbine": {"max_rpm": 0})"), "turbine.max_rpm: 0 is not in (0, 1e6]"},
      {"rpm high", preset(R"("turbine": {"max_rpm": 2e6})"), "turbine.max_rpm: 2000000.0 is not in (0, 1e6]"},
      {"removal < 0", preset(R"("cutting": {"removal_rate_mm3_per_s": -1})"), "cutting.removal_rate_mm3_per_s: -1 is not >= 0"},
      {"reach", preset(R"("cutting": {"reach_mm": 1.5})"), "cutting.reach_mm: 1.5 is not in [0, 1]"},
      {"coupling stiffness", preset(R"("coupling": {"stiffness_n_per_mm": 0})"), "coupling.stiffness_n_per_mm: 0 is not > 0"},
      {"rot stiffness", preset(R"("coupling": {"rot_stiffness_n_mm_per_rad": -1})"),
       "coupling.rot_stiffness_n_mm_per_rad: -1 is not > 0"},
      {"coupling damping", preset(R"("coupling": {"damping_n_s_per_mm": -0.001})"),
       "coupling.damping_n_s_per_mm: -0.001 is not >= 0"},
      {"rot damping", preset(R"("coupling": {"rot_damping_n_mm_s_per_rad": -1})"),
       "coupling.rot_damping_n_mm_s_per_rad: -1 is not >= 0"},
      {"proxy damping", preset(R"("coupling": {"proxy_damping_n_s_per_mm": -1})"),
       "coupling.proxy_damping_n_s_per_mm: -1 is not >= 0"},
      {"proxy speed", preset(R"("coupling": {"max_proxy_speed_mm_per_s": 0})"),
       "coupling.max_proxy_speed_mm_per_s: 0 is not > 0"},
      {"force", preset(R"("device": {"max_force_n": 0})"), "device.max_force_n: 0 is not > 0"},
      {"torque", preset(R"("device": {"max_torque_n_mm": -1})"), "device.max_torque_n_mm: -1 is not >= 0"},
      {"stale 0", preset(R"("device": {"stale_after_ms": 0})"), "device.stale_after_ms: 0 is not in (0, 100]"},
      {"stale high", preset(R"("device": {"stale_after_ms": 101})"), "device.stale_after_ms: 101 is not in (0, 100]"},
      {"rate low", preset(R"("device": {"rate_hz": 99.5})"), "device.rate_hz: 99.5 is not in [100, 10000]"},
      {"rate high", preset(R"("device": {"rate_hz": 10001})"), "device.rate_hz: 10001 is not in [100, 10000]"},
      {"head spacing", preset(R"("point_shell": {"head_spacing_mm": 0.0005})"),
       "point_shell.head_spacing_mm: 0.0005 is not in [0.001, 1]"},
      {"shank spacing", preset(R"("point_shell": {"shank_spacing_mm": 2})"),
       "point_shell.shank_spacing_mm: 2 is not in [0.001, 1]"},
  };
}

TEST(SimParams, EveryErrorIsOneLineNamingWhereAndKey) {
  int i = 0;
  for (const ErrorCase& c : errorCases()) {
    SCOPED_TRACE(c.what);
    auto r = parseSimParams(c.text, kWhere);
    ASSERT_FALSE(r.ok());
    test::assertOneLineRejection(r.message(), kWhere, i++);
    EXPECT_NE(r.message().find(kWhere + ": " + c.expected), std::string::npos)
        << r.message() << "\n  expected: " << c.expected;
  }
}

TEST(SimParams, ExampleFromTheHeader) {
  auto r = parseSimParams(preset(R"("tissues": {"enamel": {"hardness": 1.5}})"), "default.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "default.json: tissues.enamel.hardness: 1.5 is not in [0, 1]");
}

// The visual half of a preset is render's (render/look_params.h): sim accepts "looks" and "view"
// and leaves them to it, so a whole preset, old or new, reads here as its tactile half.
TEST(SimParams, AcceptsAndSkipsTheLooksAndView) {
  auto p = parseSimParams(preset(R"("tissues": {"enamel": {"hardness": 0.3}},
      "looks": {"enamel": {"alpha": 0.4, "diffuse_r": 0.5}}, "view": {"normal_neighbours": 64})"),
                          kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  SimParams expected = defaultSimParams();
  expected.tissue(Material::Enamel).hardness = 0.3;
  EXPECT_TRUE(*p == expected);
  // The tactile sections only are written.
  EXPECT_EQ(simParamsJson(*p).find("\"looks\""), std::string::npos);
  EXPECT_EQ(simParamsJson(*p).find("\"view\""), std::string::npos);
  // Any other key is still refused.
  auto other = parseSimParams(preset(R"("colours": {})"), kWhere);
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.message().find("colours"), std::string::npos) << other.message();
}

// ---- files -------------------------------------------------------------------------------------------

TEST(SimParams, SaveAndLoadRoundTrip) {
  test::TempDir dir;
  SimParams p = defaultSimParams();
  p.tissue(Material::Caries).hardness = 0.45;
  p.turbine.max_rpm = 320000.0;
  p.burs["diamond_flame"].cutting_ability = 0.95;
  const std::string path = dir.file("teacher.json");
  const Status saved = saveSimParams(path, p);
  ASSERT_TRUE(saved.ok()) << saved.message();
  auto back = loadSimParams(path);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == p);
  // The file is exactly simParamsJson, and saving again over it works.
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, simParamsJson(p));
  EXPECT_TRUE(saveSimParams(path, defaultSimParams()).ok());
  auto again = loadSimParams(path);
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_TRUE(*again == defaultSimParams());
}

TEST(SimParams, LoadErrorsNameThePath) {
  test::TempDir dir;
  const std::string missing = dir.file("missing.json");
  auto r = loadSimParams(missing);
  ASSERT_FALSE(r.ok());
  test::assertOneLineRejection(r.message(), missing, 0);

  const std::string bad = dir.file("bad.json");
  std::ofstream(bad) << preset(R"("device": {"rate_hz": 50})");
  r = loadSimParams(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), bad + ": device.rate_hz: 50 is not in [100, 10000]");

  // Over 1 MiB is refused before parsing.
  const std::string big = dir.file("big.json");
  std::ofstream(big) << preset("") << std::string(1u << 20, ' ');
  r = loadSimParams(big);
  ASSERT_FALSE(r.ok());
  test::assertOneLineRejection(r.message(), big, 0);
}

TEST(SimParams, SaveRefusesWhatCouldNotBeLoaded) {
  test::TempDir dir;
  const std::string path = dir.file("bad.json");
  SimParams p = defaultSimParams();
  p.tissue(Material::Enamel).hardness = 2.0;
  Status s = saveSimParams(path, p);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), path + ": not saved: tissues.enamel.hardness: 2.0 is not in [0, 1]");
  EXPECT_FALSE(std::filesystem::exists(path));

  p = defaultSimParams();
  p.coupling.stiffness_n_per_mm = std::numeric_limits<double>::quiet_NaN();  // written as null
  s = saveSimParams(path, p);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("coupling.stiffness_n_per_mm: expected a number, got null"), std::string::npos)
      << s.message();
  EXPECT_FALSE(std::filesystem::exists(path));
}

// ---- fuzzing -----------------------------------------------------------------------------------------

using test::pick;

// A JSON-aware change: a tricky token in place of a number, a key renamed, a line dropped or repeated.
void mutateJson(std::string& text, std::mt19937& rng) {
  static const char* const kValues[] = {"0", "-0", "1", "-1", "1e999", "-1e999", "1e-400", "0.5", "2", "1e6",
                                        "1000001", "\"x\"", "true", "null", "[]", "{}", "NaN", "Infinity",
                                        "18446744073709551616", "-9223372036854775809", "0x10", "01", "1.", ".5"};
  static const char* const kKeys[] = {"\"format\"", "\"version\"", "\"hardness\"", "\"enamel\"", "\"burs\"",
                                      "\"x y\"", "\"\"", "\"round_bur_010\"", "\"device\"", "\"\\u0000\""};
  switch (rng() % 4) {
    case 0: {  // replace the number or literal after a ':' with a tricky value
      std::vector<size_t> colons;
      for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == ':') colons.push_back(i);
      if (colons.empty()) return;
      const size_t at = colons[pick(rng, colons.size())] + 1;
      size_t end = at;
      while (end < text.size() && text[end] != ',' && text[end] != '\n' && text[end] != '}') ++end;
      text.replace(at, end - at, std::string(" ") + kValues[rng() % std::size(kValues)]);
      return;
    }
    case 1: {  // replace a quoted key with another (maybe a repeat, maybe unknown)
      std::vector<size_t> quotes;
      for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '"') quotes.push_back(i);
      if (quotes.size() < 2) return;
      const size_t q = pick(rng, quotes.size() - 1);
      text.replace(quotes[q], quotes[q + 1] - quotes[q] + 1, kKeys[rng() % std::size(kKeys)]);
      return;
    }
    default: {  // drop or repeat one line
      std::vector<size_t> starts = {0};
      for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') starts.push_back(i + 1);
      const size_t l = pick(rng, starts.size());
      const size_t begin = starts[l];
      const size_t end = l + 1 < starts.size() ? starts[l + 1] : text.size();
      const std::string line = text.substr(begin, end - begin);
      if (rng() % 2) text.erase(begin, end - begin);
      else text.insert(begin, line);
      return;
    }
  }
}

TEST(SimParamsFuzz, MutatedDefaultPresetNeverCrashesAndFailsOnOneLine) {
  const std::string original = simParamsJson(defaultSimParams());
  std::mt19937 rng(20250611u);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < 3000; ++it) {
    std::string text = original;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      std::vector<uint8_t> bytes(text.begin(), text.end());
      if (test::mutateBytesGeneric(bytes, rng)) text.assign(bytes.begin(), bytes.end());
      else mutateJson(text, rng);
    }
    auto r = parseSimParams(text, kWhere);
    if (r.ok()) {
      ++accepted;
      // What was accepted writes out and reads back the same.
      auto again = parseSimParams(simParamsJson(*r), kWhere);
      ASSERT_TRUE(again.ok()) << "iteration " << it << ": " << again.message();
      ASSERT_TRUE(*again == *r) << "iteration " << it;
    } else {
      ++rejected;
      test::assertOneLineRejection(r.message(), kWhere, it);
      if (::testing::Test::HasFatalFailure()) return;
      // Every rejection is one the reader meant, not an exception it caught as a last resort.
      ASSERT_EQ(r.message().find("cannot read preset"), std::string::npos) << r.message();
    }
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace dentsim
