// Shared by the parsers' bounded fuzz tests: byte mutations (flips, boundary bytes, runs, truncation) and the rejection check.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <iterator>
#include <random>
#include <vector>

namespace dentsim::test {

inline size_t pick(std::mt19937& rng, size_t n) { return n == 0 ? 0 : size_t(rng() % n); }

// Applies one generic mutation and returns true, or returns false (in 2 of 7 draws) so that the
// caller applies one of its format's own mutations instead.
inline bool mutateBytesGeneric(std::vector<uint8_t>& bytes, std::mt19937& rng) {
  static const uint8_t kBoundary[] = {0x00, 0x01, 0x02, 0x03, 0x04, 0x0a, 0x0d, 0x20, 0x7f, 0x80, 0xff};
  switch (rng() % 7) {
    case 0:
      if (!bytes.empty()) bytes[pick(rng, bytes.size())] ^= uint8_t(1u << (rng() % 8));
      return true;
    case 1:
      if (!bytes.empty()) bytes[pick(rng, bytes.size())] = kBoundary[rng() % std::size(kBoundary)];
      return true;
    case 2: {
      const size_t at = pick(rng, bytes.size() + 1);
      std::vector<uint8_t> run(1 + pick(rng, 16));
      for (uint8_t& b : run) b = uint8_t(rng());
      bytes.insert(bytes.begin() + std::ptrdiff_t(at), run.begin(), run.end());
      return true;
    }
    case 3: {
      if (bytes.empty()) return true;
      const size_t at = pick(rng, bytes.size());
      const size_t n = std::min(bytes.size() - at, 1 + pick(rng, 50));
      bytes.erase(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + n));
      return true;
    }
    case 4:
      bytes.resize(pick(rng, bytes.size() + 1));
      return true;
    default:
      return false;
  }
}

// A rejected file's error must be one non-empty line that starts with the source's name.
inline void assertOneLineRejection(const std::string& message, const std::string& where, int iteration) {
  ASSERT_EQ(message.rfind(where + ": ", 0), 0u) << message;
  ASSERT_GT(message.size(), where.size() + 2) << "iteration " << iteration;
  ASSERT_EQ(message.find('\n'), std::string::npos) << message;
  ASSERT_EQ(message.find('\r'), std::string::npos) << message;
}

}  // namespace dentsim::test
