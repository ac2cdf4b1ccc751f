// Tests of src/io/param_fields.cpp: the table-driven field reader and the one preset reader the three parsers share.
#include "io/param_fields.h"

#include <gtest/gtest.h>

#include <string>

namespace dentsim {
namespace {

using json = nlohmann::json;

// A two-field struct stands in for a stage's params: one open range, one closed, so both ends show.
struct Knob {
  double gain_n_per_mm;  // > 0
  double mix;            // in [0, 1]
};
const Field<Knob> kKnobFields[] = {
    {"gain_n_per_mm", &Knob::gain_n_per_mm, kPositive},
    {"mix", &Knob::mix, kUnit},
};

// Reads `text` (one object) as a Knob over {2, 0.5}; the error, or "" when it reads.
std::string readKnob(const std::string& text, Knob* out) {
  *out = {2.0, 0.5};
  FieldReader r;
  r.fields(json::parse(text), "knob", kKnobFields, out);
  return r.error();
}

std::string preset(const std::string& body) {
  return std::string(R"({"format": "dentsim-params", "version": 1)") + (body.empty() ? "" : ", " + body) + "}";
}

TEST(ParamFields, FieldsOverrideOnlyTheKeysTheyName) {
  Knob k;
  EXPECT_EQ(readKnob(R"({"mix": 0.25})", &k), "");
  EXPECT_EQ(k.gain_n_per_mm, 2.0);  // left out: the default stays
  EXPECT_EQ(k.mix, 0.25);
  EXPECT_EQ(readKnob("{}", &k), "");
  EXPECT_EQ(k.gain_n_per_mm, 2.0);
  EXPECT_EQ(k.mix, 0.5);
}

TEST(ParamFields, RangeEndsFollowTheTable) {
  Knob k;
  // kUnit is closed at both ends; kPositive is open at 0.
  EXPECT_EQ(readKnob(R"({"mix": 0, "gain_n_per_mm": 1e-300})", &k), "");
  EXPECT_EQ(readKnob(R"({"mix": 1})", &k), "");
  EXPECT_EQ(readKnob(R"({"mix": 1.5})", &k), "knob.mix: 1.5 is not in [0, 1]");
  EXPECT_EQ(readKnob(R"({"mix": -0.1})", &k), "knob.mix: -0.1 is not in [0, 1]");
  EXPECT_EQ(readKnob(R"({"gain_n_per_mm": 0})", &k), "knob.gain_n_per_mm: 0 is not > 0");
  // A refused value leaves the field as it was.
  EXPECT_EQ(k.gain_n_per_mm, 2.0);
}

TEST(ParamFields, UnknownKeyListsTheKnownOnes) {
  Knob k;
  EXPECT_EQ(readKnob(R"({"mix": 0.1, "gain": 3})", &k), "knob.gain: unknown key (known: gain_n_per_mm, mix)");
}

TEST(ParamFields, WrongTypesAreNamed) {
  Knob k;
  EXPECT_EQ(readKnob(R"({"mix": "0.5"})", &k), "knob.mix: expected a number, got string");
  EXPECT_EQ(readKnob(R"({"mix": null})", &k), "knob.mix: expected a number, got null");
  EXPECT_EQ(readKnob(R"({"mix": true})", &k), "knob.mix: expected a number, got boolean");
  EXPECT_EQ(readKnob("[1, 2]", &k), "knob: expected an object, got array");
}

TEST(ParamFields, TheFirstProblemWins) {
  Knob k{2.0, 0.5};
  FieldReader r;
  EXPECT_FALSE(r.fields(json::parse(R"({"mix": 7})"), "a", kKnobFields, &k));
  EXPECT_FALSE(r.fields(json::parse(R"({"nope": 1})"), "b", kKnobFields, &k));
  EXPECT_EQ(r.error(), "a.mix: 7 is not in [0, 1]");
}

TEST(ParamFields, AMissingSectionKeepsTheValues) {
  Knob k{2.0, 0.5};
  FieldReader r;
  EXPECT_TRUE(r.section(json::parse(R"({"other": 1})"), "knob", kKnobFields, &k));
  EXPECT_EQ(k.mix, 0.5);
  EXPECT_TRUE(r.section(json::parse(R"({"knob": {"mix": 0.75}})"), "knob", kKnobFields, &k));
  EXPECT_EQ(k.mix, 0.75);
  EXPECT_FALSE(r.section(json::parse(R"({"knob": 3})"), "knob", kKnobFields, &k));
  EXPECT_EQ(r.error(), "knob: expected an object, got number");
}

TEST(ParamFields, WrittenFieldsReadBackEqual) {
  const Knob k{0.1 + 0.2, 1.0 / 3.0};  // neither is short in decimal
  const std::string text = presetText(fieldsJson(k, kKnobFields));
  EXPECT_EQ(text.back(), '\n');
  Knob back{2.0, 0.5};
  FieldReader r;
  ASSERT_TRUE(r.fields(json::parse(text), "knob", kKnobFields, &back)) << r.error();
  EXPECT_TRUE(sameFields(k, back, kKnobFields));
}

// readPreset: the header first, then the caller's sections, and every error prefixed with `where`.
TEST(ParamFields, ReadPresetChecksTheHeaderBeforeTheSections) {
  Knob k{2.0, 0.5};
  int calls = 0;
  auto knobSection = [&](const json& root, FieldReader& r) {
    ++calls;
    // "device" stands in for a stage's section: the header allows only the preset's own keys.
    r.section(root, "device", kKnobFields, &k);
  };
  EXPECT_TRUE(readPreset(preset(R"("device": {"mix": 0.125})"), "p.json", knobSection).ok());
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(k.mix, 0.125);

  Status range = readPreset(preset(R"("device": {"mix": 2})"), "p.json", knobSection);
  ASSERT_FALSE(range.ok());
  EXPECT_EQ(range.message(), "p.json: device.mix: 2 is not in [0, 1]");

  // A refused header never reaches the sections.
  calls = 0;
  Status format = readPreset(R"({"format": "dentsim-task", "version": 1})", "p.json", knobSection);
  ASSERT_FALSE(format.ok());
  EXPECT_EQ(format.message(), "p.json: format: \"dentsim-task\" is not \"dentsim-params\"");
  Status version = readPreset(R"({"format": "dentsim-params", "version": 2})", "p.json", knobSection);
  ASSERT_FALSE(version.ok());
  EXPECT_EQ(version.message(), "p.json: version: 2 is not supported (this build reads version 1)");
  Status top = readPreset(preset(R"("colours": {})"), "p.json", knobSection);
  ASSERT_FALSE(top.ok());
  EXPECT_EQ(top.message().rfind("p.json: colours: unknown key (known: format, version, tissues", 0), 0u)
      << top.message();
  Status array = readPreset("[]", "p.json", knobSection);
  ASSERT_FALSE(array.ok());
  EXPECT_EQ(array.message(), "p.json: (top level): expected an object, got array");
  EXPECT_EQ(calls, 0);
}

TEST(ParamFields, ReadPresetRefusesBadJsonOnOneLine) {
  auto none = [](const json&, FieldReader&) {};
  Status syntax = readPreset("{\"format\": ", "p.json", none);
  ASSERT_FALSE(syntax.ok());
  EXPECT_EQ(syntax.message().rfind("p.json: invalid JSON: ", 0), 0u) << syntax.message();
  Status repeated = readPreset(R"({"format": "dentsim-params", "format": "x", "version": 1})", "p.json", none);
  ASSERT_FALSE(repeated.ok());
  EXPECT_EQ(repeated.message(), "p.json: format: repeated key");
  // A file name holding a newline stays on one line.
  Status named = readPreset("[]", "a\nb.json", none);
  ASSERT_FALSE(named.ok());
  EXPECT_EQ(named.message().find('\n'), std::string::npos) << named.message();
}

}  // namespace
}  // namespace dentsim
