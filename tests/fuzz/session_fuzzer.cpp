// libFuzzer entry for the session reader: the input is parsed as a .dses file as it is and with its checksums made right, and an accepted recording must encode and read back unchanged.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include <xxhash.h>

#include "io/session_file.h"

namespace {

dentsim::SessionReadLimits fuzzLimits() {
  dentsim::SessionReadLimits limits;
  limits.max_steps = uint64_t{1} << 16;  // a long input must not make the fuzzer run out of memory
  limits.max_header_bytes = 1u << 20;
  limits.max_record_bytes = 1u << 20;
  return limits;
}

// Random bytes almost never carry right checksums, which would stop the fuzzer at the first one;
// this copy has them recomputed wherever the lengths frame a header or a record.
std::vector<uint8_t> withChecksums(const uint8_t* data, size_t size) {
  std::vector<uint8_t> b(data, data + size);
  if (b.size() < 16) return b;
  uint32_t length = 0;
  std::memcpy(&length, b.data() + 12, 4);
  size_t at = 16 + size_t(length);
  if (at + 8 > b.size()) return b;
  const uint64_t header_sum = XXH64(b.data() + 16, length, 0);
  std::memcpy(b.data() + at, &header_sum, 8);
  at += 8;
  while (at + 8 <= b.size()) {
    std::memcpy(&length, b.data() + at + 4, 4);
    const size_t end = at + 8 + size_t(length);
    if (end + 4 > b.size()) break;
    const uint32_t sum = XXH32(b.data() + at, 8 + size_t(length), 0);
    std::memcpy(b.data() + end, &sum, 4);
    at = end + 4;
  }
  return b;
}

// What the reader accepts, encodeSession must write so that it reads back the same: whole records,
// no truncation left, and the very same bytes when encoded again.
void check(std::span<const uint8_t> input) {
  const dentsim::SessionReadLimits limits = fuzzLimits();
  const auto read = dentsim::parseSession(input, "fuzz.dses", limits);
  if (!read.ok()) {
    if (read.message().empty()) std::abort();
    return;
  }
  const std::vector<uint8_t> bytes = dentsim::encodeSession(*read);
  const auto again = dentsim::parseSession(bytes, "fuzz.dses", limits);
  if (!again.ok() || !again->truncation_warning.empty() || again->steps.size() != read->steps.size() ||
      again->params.size() != read->params.size() || again->gaps.size() != read->gaps.size() ||
      again->end.has_value() != read->end.has_value() || dentsim::encodeSession(*again) != bytes)
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check(std::span(data, size));
  check(withChecksums(data, size));
  return 0;
}
