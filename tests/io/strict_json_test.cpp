// Tests of src/io/strict_json.cpp: the depth limit, its message, and that ordinary files parse as before.
#include "io/strict_json.h"

#include <gtest/gtest.h>

#include <string>

namespace dentsim {
namespace {

std::string nested(int depth, char open = '[', char close = ']') {
  return std::string(size_t(depth), open) + std::string(size_t(depth), close);
}

TEST(StrictJson, NestingUpToTheLimitParses) {
  nlohmann::json j;
  std::string error;
  ASSERT_TRUE(parseStrictJson(nested(kMaxJsonDepth), &j, &error)) << error;
  // 64 arrays, each holding the next: descending 63 times reaches the empty innermost one.
  const nlohmann::json* at = &j;
  for (int i = 1; i < kMaxJsonDepth; ++i) at = &(*at)[0];
  EXPECT_TRUE(at->is_array() && at->empty());
}

TEST(StrictJson, OneLevelPastTheLimitIsRefusedWithItsPosition) {
  nlohmann::json j;
  std::string error;
  // The 65th '[' is column 65 of line 1.
  EXPECT_FALSE(parseStrictJson(nested(kMaxJsonDepth + 1), &j, &error));
  EXPECT_EQ(error, "invalid JSON: nested deeper than 64 levels at line 1, column 65");
}

TEST(StrictJson, AHundredThousandDeepIsRefusedWithABoundedMessage) {
  // The issue's 600 KB file: objects keyed "a", 100 000 deep. Before the limit, it cost 10 GB.
  std::string text;
  for (int i = 0; i < 100000; ++i) text += "{\"a\":";
  text += "1";
  text += std::string(100000, '}');
  nlohmann::json j;
  std::string error;
  EXPECT_FALSE(parseStrictJson(text, &j, &error));
  // Each level is 5 bytes, so the 65th '{' is at column 5 * 64 + 1.
  EXPECT_EQ(error, "invalid JSON: nested deeper than 64 levels at line 1, column 321");
}

TEST(StrictJson, BracketsInsideStringsDoNotCount) {
  nlohmann::json j;
  std::string error;
  const std::string text = "{\"name\": \"" + std::string(200, '[') + "\\\"{{{\", \"n\": [1]}";
  ASSERT_TRUE(parseStrictJson(text, &j, &error)) << error;
  EXPECT_EQ(j["name"].get<std::string>(), std::string(200, '[') + "\"{{{");
}

TEST(StrictJson, TheDepthPositionCountsLines) {
  nlohmann::json j;
  std::string error;
  std::string text = "{\n";
  for (int i = 1; i < kMaxJsonDepth; ++i) text += "\"k\": {\n";
  text += "  \"deep\": [1]";  // the 65th bracket: line 65, column 11
  for (int i = 0; i < kMaxJsonDepth; ++i) text += "}";
  EXPECT_FALSE(parseStrictJson(text, &j, &error));
  EXPECT_EQ(error, "invalid JSON: nested deeper than 64 levels at line 65, column 11");
}

TEST(StrictJson, RepeatedKeysAndHugeNumbersStillNameTheirPath) {
  nlohmann::json j;
  std::string error;
  EXPECT_FALSE(parseStrictJson(R"({"tissues": {"enamel": {"hardness": 1, "hardness": 2}}})", &j, &error));
  EXPECT_EQ(error, "tissues.enamel.hardness: repeated key");
  EXPECT_FALSE(parseStrictJson(R"({"a": [{"odd key": 1e999}]})", &j, &error));
  EXPECT_EQ(error.rfind("a[].\"odd key\": not a finite number", 0), 0u) << error;
  // The same key in two objects is not a repeat.
  ASSERT_TRUE(parseStrictJson(R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 3}, {"x": 4}]})", &j, &error)) << error;
  EXPECT_EQ(j["c"][1]["x"].get<int>(), 4);
}

}  // namespace
}  // namespace dentsim
