// Bounded, deterministic mutation fuzzing of parseStrictJson: deep nesting, bracket runs and broken text never crash it or cost more than linear memory, and every failure is one line.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "io/strict_json.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

using test::pick;

// How deep a parsed value nests (an empty document counts 0): never more than the limit.
int depthOf(const nlohmann::json& j) {
  if (!j.is_structured()) return 0;
  int deepest = 0;
  for (const auto& child : j) deepest = std::max(deepest, depthOf(child));
  return deepest + 1;
}

const std::string kPreset = R"({"tissues": {"enamel": {"hardness": 0.1, "colour": [250, 245, 230]},
  "dentin": {"hardness": 0.1}}, "view": {"fov_deg": 40, "names": ["a", "b\"[{", "c"]}, "ok": true})";

// One JSON-aware change: wrap the text in a run of brackets (up to far past the limit), insert a run
// of openers or closers, or insert a quote, a key or a huge number.
void mutateJson(std::string& text, std::mt19937& rng) {
  static const char* const kBits[] = {"\"", "\\", ",", ":", "{\"k\":", "1e999", "-", "null", "\"k\": 1,", "]", "}"};
  const size_t at = pick(rng, text.size() + 1);
  switch (rng() % 4) {
    case 0: {
      static const size_t kDepths[] = {1, 10, 62, 63, 64, 65, 100, 5000, 100000};
      const size_t n = kDepths[pick(rng, std::size(kDepths))];
      const bool arrays = rng() % 2;
      std::string open, close;
      for (size_t i = 0; i < n; ++i) open += arrays ? "[" : "{\"a\":";
      close.assign(n, arrays ? ']' : '}');
      text = open + text + close;
      break;
    }
    case 1: text.insert(at, std::string(1 + pick(rng, 200), "[{]}"[rng() % 4])); break;
    default: text.insert(at, kBits[pick(rng, std::size(kBits))]); break;
  }
}

TEST(StrictJsonFuzzTest, DeepAndBrokenTextIsRefusedInOneLine) {
  std::mt19937 rng(27);
  int accepted = 0, rejected = 0, too_deep = 0;
  for (int it = 0; it < 3000; ++it) {
    std::string text = kPreset;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      std::vector<uint8_t> bytes(text.begin(), text.end());
      if (test::mutateBytesGeneric(bytes, rng)) text.assign(bytes.begin(), bytes.end());
      else mutateJson(text, rng);
    }
    nlohmann::json j;
    std::string error;
    if (parseStrictJson(text, &j, &error)) {
      ++accepted;
      ASSERT_LE(depthOf(j), kMaxJsonDepth) << "iteration " << it;
    } else {
      ++rejected;
      too_deep += error.find("nested deeper than 64 levels") != std::string::npos;
      ASSERT_FALSE(error.empty());
      ASSERT_EQ(error.find('\n'), std::string::npos) << error;
      ASSERT_LT(error.size(), 400u) << error;  // bounded whatever the input
    }
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(too_deep, 0);
}

}  // namespace
}  // namespace dentsim
