// Shared by the parsers' bounded fuzz tests: byte mutations (flips, boundary bytes, runs, truncation) and the rejection check.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
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

// Puts the magic bytes of another format (io/file_kind.h) at the start of `bytes`: the files a
// careless user hands a reader (a PLY as STL, a .nii.gz as .dvol). NIfTI's magic sits at byte 344,
// so that one grows the input to a whole header.
inline void overwriteWithForeignMagic(std::vector<uint8_t>& bytes, std::mt19937& rng) {
  static const std::vector<std::vector<uint8_t>> kMagics = {
      {'p', 'l', 'y', '\n'},        {0x1f, 0x8b, 0x08},           {0x28, 0xb5, 0x2f, 0xfd},
      {'D', 'E', 'N', 'T', 'S', 'I', 'M', 'V'}, {'D', 'S', 'E', 'S', 'S', 'I', 'O', 'N'},
      {'R', 'I', 'F', 'F', 0, 0, 0, 0, 'W', 'A', 'V', 'E'},  {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'},
      {0x5c, 0x01, 0x00, 0x00},      // NIfTI-1 sizeof_hdr 348, little-endian; "n+1" follows at 344
  };
  const std::vector<uint8_t>& magic = kMagics[pick(rng, std::size(kMagics))];
  if (bytes.size() < magic.size()) bytes.resize(magic.size());
  std::copy(magic.begin(), magic.end(), bytes.begin());
  if (magic[0] == 0x5c) {
    if (bytes.size() < 352) bytes.resize(352);
    const uint8_t n1[4] = {'n', '+', '1', 0};
    std::copy(std::begin(n1), std::end(n1), bytes.begin() + 344);
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
