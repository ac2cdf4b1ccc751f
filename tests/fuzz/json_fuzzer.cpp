// libFuzzer entry for the strict JSON parser of presets and tasks: any input parses within the depth limit or fails in one line.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/strict_json.h"

namespace {

int depthOf(const nlohmann::json& j) {
  if (!j.is_structured()) return 0;
  int deepest = 0;
  for (const auto& child : j) deepest = std::max(deepest, depthOf(child));
  return deepest + 1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  nlohmann::json j;
  std::string error;
  if (dentsim::parseStrictJson(text, &j, &error)) {
    if (depthOf(j) > dentsim::kMaxJsonDepth) std::abort();
  } else if (error.empty() || error.find('\n') != std::string::npos) {
    std::abort();
  }
  return 0;
}
