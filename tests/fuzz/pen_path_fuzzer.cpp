// libFuzzer entry for the pen path readers: the input is parsed in memory as CSV and as JSON, and an accepted path must save and read back unchanged.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/pen_path_file.h"

namespace {

// What a reader accepts, the writers must write so that it reads back the same.
void checkRoundTrip(const dentsim::Result<dentsim::PenPath>& path, const dentsim::PenPathReadLimits& limits) {
  if (!path.ok()) return;
  if (!dentsim::checkPenPath(*path, "fuzz").ok()) std::abort();
  const auto csv = dentsim::parsePenPathCsv(dentsim::penPathCsv(*path), "fuzz.csv", limits);
  const auto json = dentsim::parsePenPathJson(dentsim::penPathJson(*path), "fuzz.json", limits);
  if (!csv.ok() || !json.ok() || !(*csv == *path) || !(*json == *path)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dentsim::PenPathReadLimits limits;
  limits.max_samples = uint64_t{1} << 16;  // a long input must not make the fuzzer run out of memory
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  checkRoundTrip(dentsim::parsePenPathCsv(text, "fuzz.csv", limits), limits);
  checkRoundTrip(dentsim::parsePenPathJson(text, "fuzz.json", limits), limits);
  return 0;
}
