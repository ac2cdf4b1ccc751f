// Tests of src/ui/preset.cpp: a whole preset file, sim's and render's sections, written and read back as one.
#include "ui/preset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <span>
#include <string>

#include "model/builtin_assets.h"
#include "test_support.h"

namespace dentsim::ui {
namespace {

const std::string kWhere = "t.json";

std::string preset(const std::string& body) {
  return std::string(R"({"format": "dentsim-params", "version": 1)") + (body.empty() ? "" : ", " + body) + "}";
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The checked-in assets/presets/default.json (as embedded) must be exactly what the code writes, so
// that the file and the defaults cannot drift apart. On a mismatch, regenerate the file from
// presetJson(defaultPreset()) and rebuild.
TEST(Preset, CheckedInDefaultPresetEqualsDefaults) {
  const std::span<const uint8_t> embedded = builtinAssetBytes("presets/default.json");
  ASSERT_FALSE(embedded.empty()) << "assets/presets/default.json is not embedded";
  const std::string text(embedded.begin(), embedded.end());
  EXPECT_EQ(text, presetJson(defaultPreset()));
  auto p = parsePreset(text, "presets/default.json");
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_TRUE(*p == defaultPreset());
}

// Sim's sections first, then render's, in the one fixed order of the file.
TEST(Preset, JsonHasTheFixedLayout) {
  const std::string text = presetJson(defaultPreset());
  const char* sections[] = {"\"format\"", "\"version\"", "\"tissues\"",    "\"burs\"",  "\"turbine\"", "\"cutting\"",
                            "\"coupling\"", "\"device\"", "\"point_shell\"", "\"looks\"", "\"view\""};
  size_t at = 0;
  for (const char* s : sections) {
    const size_t found = text.find(std::string("\n  ") + s, at);
    ASSERT_NE(found, std::string::npos) << s;
    at = found;
  }
  EXPECT_NE(text.find("\"view\": {\n    \"normal_neighbours\": 216.0\n  }\n}\n"), std::string::npos);
}

// A preset written and read back is the same to the bit, and writes the same text again.
TEST(Preset, AwkwardValuesRoundTripBitIdentical) {
  Preset p = defaultPreset();
  p.sim.tissue(Material::Enamel).hardness = 0.1 + 0.2;
  p.sim.coupling.rot_damping_n_mm_s_per_rad = -0.0;
  p.sim.burs["custom-bur.1"].cutting_ability = 1.0 / 7.0;
  p.looks.look(Material::Dentin).diffuse_g = 1.0 / 3.0;
  p.looks.look(Material::Pulp).ambient_b = std::numeric_limits<double>::denorm_min();
  p.looks.look(Material::Caries).shininess = std::nextafter(512.0, 0.0);
  p.looks.view.normals = NormalMode::Box8;
  const std::string text = presetJson(p);
  auto back = parsePreset(text, kWhere);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == p);
  EXPECT_EQ(presetJson(*back), text);
  EXPECT_TRUE(sameBits(back->sim.tissue(Material::Enamel).hardness, 0.1 + 0.2));
  EXPECT_TRUE(sameBits(back->sim.coupling.rot_damping_n_mm_s_per_rad, -0.0));
  EXPECT_TRUE(sameBits(back->looks.look(Material::Dentin).diffuse_g, 1.0 / 3.0));
  EXPECT_TRUE(sameBits(back->looks.look(Material::Pulp).ambient_b, std::numeric_limits<double>::denorm_min()));
  EXPECT_TRUE(sameBits(back->looks.look(Material::Caries).shininess, std::nextafter(512.0, 0.0)));
  // Each stage reads its own half of the same text.
  auto sim = parseSimParams(text, kWhere);
  ASSERT_TRUE(sim.ok()) << sim.message();
  EXPECT_TRUE(*sim == p.sim);
  auto looks = parseLookParams(text, kWhere);
  ASSERT_TRUE(looks.ok()) << looks.message();
  EXPECT_TRUE(*looks == p.looks);
}

// A partial preset with both halves, as presets have always been written, fills both.
TEST(Preset, PartialPresetFillsBothHalves) {
  auto p = parsePreset(preset(R"("tissues": {"pulp": {"friction": 0.5}}, "looks": {"pulp": {"alpha": 0.5}},
      "view": {"normal_neighbours": 64})"),
                       kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  Preset expected = defaultPreset();
  expected.sim.tissue(Material::Pulp).friction = 0.5;
  expected.looks.look(Material::Pulp).alpha = 0.5;
  expected.looks.view.normals = NormalMode::Box64;
  EXPECT_TRUE(*p == expected);
}

// The first problem in file order is the one named: tactile sections come before the looks.
TEST(Preset, ErrorsNameTheFirstProblemInFileOrder) {
  auto both = parsePreset(preset(R"("looks": {"pulp": {"alpha": 1.2}}, "tissues": {"enamel": {"hardness": 1.5}})"),
                          kWhere);
  ASSERT_FALSE(both.ok());
  EXPECT_EQ(both.message(), "t.json: tissues.enamel.hardness: 1.5 is not in [0, 1]");
  auto look = parsePreset(preset(R"("looks": {"pulp": {"alpha": 1.2}})"), kWhere);
  ASSERT_FALSE(look.ok());
  EXPECT_EQ(look.message(), "t.json: looks.pulp.alpha: 1.2 is not in [0, 1]");
  auto version = parsePreset(R"({"format": "dentsim-params", "version": 2})", kWhere);
  ASSERT_FALSE(version.ok());
  EXPECT_EQ(version.message(), "t.json: version: 2 is not supported (this build reads version 1)");
}

TEST(Preset, SaveAndLoadRoundTripAndRefuseWhatWouldNotLoad) {
  test::TempDir dir;
  Preset p = defaultPreset();
  p.sim.turbine.max_rpm = 320000.0;
  p.looks.look(Material::Enamel).alpha = 0.25;
  const std::string path = dir.file("teacher.json");
  const Status saved = savePreset(path, p);
  ASSERT_TRUE(saved.ok()) << saved.message();
  auto back = loadPreset(path);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == p);
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, presetJson(p));

  Preset bad = p;
  bad.looks.look(Material::Dentin).shininess = 0.0;
  const Status refused = savePreset(dir.file("bad.json"), bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("looks.dentin.shininess"), std::string::npos) << refused.message();
  auto missing = loadPreset(dir.file("bad.json"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("bad.json"), std::string::npos) << missing.message();
}

}  // namespace
}  // namespace dentsim::ui
