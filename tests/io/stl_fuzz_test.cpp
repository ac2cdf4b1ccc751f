// Bounded, deterministic mutation fuzzing of parseStl: hostile bytes and text never crash it, and every failure is one clear line.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "io/stl_file.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

const std::string kWhere = "fuzz.stl";

// A closed octahedron: 6 corners, 8 triangles, small enough that a case parses in microseconds.
TriangleMesh octahedron() {
  TriangleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

// Tight, so that a forged count could not make a case allocate much even if a check failed.
StlReadLimits fuzzLimits() {
  StlReadLimits limits;
  limits.max_triangles = 4096;
  return limits;
}

// Accepted meshes must be usable as they are; rejections must be one line naming the source.
void checkOutcome(const Result<StlMesh>& r, int iteration, int* accepted, int* rejected) {
  if (r.ok()) {
    ++*accepted;
    const TriangleMesh& m = r->mesh;
    ASSERT_GT(m.triangleCount(), 0u) << "iteration " << iteration;
    ASSERT_LE(r->info.file_triangles, fuzzLimits().max_triangles) << "iteration " << iteration;
    ASSERT_EQ(r->info.file_triangles, m.triangleCount() + r->info.dropped_triangles) << "iteration " << iteration;
    for (const auto& t : m.triangles)
      for (uint32_t c : t) ASSERT_LT(c, m.vertexCount()) << "iteration " << iteration;
    for (const Vec3f& p : m.positions)
      for (float v : p) ASSERT_TRUE(std::isfinite(v)) << "iteration " << iteration;
  } else {
    ++*rejected;
    test::assertOneLineRejection(r.message(), kWhere, iteration);
  }
}

using test::pick;

// One random byte-level change: flip a bit, write a boundary value, insert or delete a run, cut the
// tail, or (for binary files) rewrite the triangle count at offset 80.
void mutateBytes(std::vector<uint8_t>& bytes, std::mt19937& rng) {
  if (test::mutateBytesGeneric(bytes, rng)) return;
  if (rng() % 8 == 0) return test::overwriteWithForeignMagic(bytes, rng);  // a PLY, .nii.gz, .dvol ... as STL
  switch (rng() % 2) {
    case 0: {  // a non-finite or huge float in a corner
      if (bytes.size() < 4) break;
      static const uint32_t kFloats[] = {0x7fc00000u, 0x7f800000u, 0xff800000u, 0x7f7fffffu, 0x00000001u, 0x80000000u};
      const uint32_t w = kFloats[rng() % 6];
      std::memcpy(bytes.data() + pick(rng, bytes.size() - 3), &w, 4);
      break;
    }
    default: {  // the count field: off by one, zero, huge, or one that matches a different size
      if (bytes.size() < 84) break;
      uint32_t count = 0;
      std::memcpy(&count, bytes.data() + 80, 4);
      static const uint32_t kCounts[] = {0u, 1u, 0xffffffffu, 0x80000000u, 0x05555555u};
      switch (rng() % 4) {
        case 0: count += 1; break;
        case 1: count -= 1; break;
        case 2: count = kCounts[rng() % 5]; break;
        default: count = uint32_t(rng()); break;
      }
      std::memcpy(bytes.data() + 80, &count, 4);
      break;
    }
  }
}

// Splits text at whitespace into tokens and the whitespace between them, so that a token edit keeps
// the layout and a whitespace edit keeps the tokens.
struct Pieces {
  std::vector<std::string> tokens;  // tokens[i] follows spaces[i]
  std::vector<std::string> spaces;
  std::string tail;                 // whitespace after the last token

  static Pieces split(const std::string& text) {
    Pieces p;
    size_t i = 0;
    for (;;) {
      const size_t start = i;
      while (i < text.size() && std::isspace(uint8_t(text[i]))) ++i;
      if (i == text.size()) {
        p.tail = text.substr(start);
        return p;
      }
      p.spaces.push_back(text.substr(start, i - start));
      const size_t tok = i;
      while (i < text.size() && !std::isspace(uint8_t(text[i]))) ++i;
      p.tokens.push_back(text.substr(tok, i - tok));
    }
  }
  std::string join() const {
    std::string out;
    for (size_t i = 0; i < tokens.size(); ++i) out += spaces[i] + tokens[i];
    return out + tail;
  }
};

// One random token-level change: swap in a keyword or a tricky number, drop or repeat a token,
// change its case, or change the whitespace before it.
void mutateTokens(Pieces& p, std::mt19937& rng) {
  static const std::vector<std::string> kTokens = {
      "solid", "endsolid", "facet", "endfacet", "normal", "outer", "loop", "endloop", "vertex", "VERTEX",
      "0", "-0", "1", "+1", "1e38", "1e39", "-1e39", "1e-50", "1e-400", "nan", "-nan", "inf", "-inf",
      "infinity", "nan(0x7)", "0x10", "1.0.0", "--1", "+-1", "1e", ".", "+", "-", "3.4028235e38",
      "1.17549435e-38", "4294967295", "garbage", "\xc2\xb5", std::string(300, '9'),
  };
  static const char* const kSpaces[] = {" ", "\n", "\r\n", "\t", "", "\n\n\n", "\r", "\v\f"};
  if (p.tokens.empty()) {
    p.tokens.push_back(kTokens[rng() % kTokens.size()]);
    p.spaces.push_back("");
    return;
  }
  const size_t i = pick(rng, p.tokens.size());
  switch (rng() % 6) {
    case 0: p.tokens[i] = kTokens[rng() % kTokens.size()]; break;
    case 1:
      p.tokens.erase(p.tokens.begin() + std::ptrdiff_t(i));
      p.spaces.erase(p.spaces.begin() + std::ptrdiff_t(i));
      break;
    case 2:
      p.tokens.insert(p.tokens.begin() + std::ptrdiff_t(i), p.tokens[pick(rng, p.tokens.size())]);
      p.spaces.insert(p.spaces.begin() + std::ptrdiff_t(i), " ");
      break;
    case 3:
      for (char& c : p.tokens[i]) c = char(rng() % 2 ? std::toupper(uint8_t(c)) : std::tolower(uint8_t(c)));
      break;
    case 4: p.spaces[i] = kSpaces[rng() % std::size(kSpaces)]; break;
    default: {  // a whole facet repeated, or cut short, by moving a run of tokens
      const size_t n = std::min(p.tokens.size() - i, 1 + pick(rng, 20));
      if (rng() % 2) {
        p.tokens.erase(p.tokens.begin() + std::ptrdiff_t(i), p.tokens.begin() + std::ptrdiff_t(i + n));
        p.spaces.erase(p.spaces.begin() + std::ptrdiff_t(i), p.spaces.begin() + std::ptrdiff_t(i + n));
      } else {
        const std::vector<std::string> t(p.tokens.begin() + std::ptrdiff_t(i), p.tokens.begin() + std::ptrdiff_t(i + n));
        const std::vector<std::string> s(p.spaces.begin() + std::ptrdiff_t(i), p.spaces.begin() + std::ptrdiff_t(i + n));
        p.tokens.insert(p.tokens.begin() + std::ptrdiff_t(i), t.begin(), t.end());
        p.spaces.insert(p.spaces.begin() + std::ptrdiff_t(i), s.begin(), s.end());
      }
      break;
    }
  }
}

void fuzzBinary(const std::string& header, uint32_t seed, int iterations) {
  const std::vector<uint8_t> original = encodeStlBinary(octahedron(), header);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> bytes = original;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) mutateBytes(bytes, rng);
    checkOutcome(parseStl(bytes, kWhere, fuzzLimits()), it, &accepted, &rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0) << header;
  EXPECT_GT(rejected, 0) << header;
}

void fuzzAscii(uint32_t seed, int iterations, bool byte_edits) {
  const std::string original = encodeStlAscii(octahedron(), "octahedron");
  const Pieces pieces = Pieces::split(original);
  ASSERT_EQ(pieces.join(), original);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    Pieces p = pieces;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) mutateTokens(p, rng);
    const std::string text = p.join();
    std::vector<uint8_t> bytes(text.begin(), text.end());
    if (byte_edits) mutateBytes(bytes, rng);
    checkOutcome(parseStl(bytes, kWhere, fuzzLimits()), it, &accepted, &rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(StlFuzzTest, MutatedBinaryFiles) {
  fuzzBinary("dentsim fuzz seed", 20240611u, 2000);
}

// A header that starts with "solid" sends every size mismatch down the ASCII path.
TEST(StlFuzzTest, MutatedBinaryFilesWithSolidHeader) {
  fuzzBinary("solid octahedron", 99u, 1500);
}

TEST(StlFuzzTest, MutatedAsciiTokens) {
  fuzzAscii(7u, 2500, false);
}

TEST(StlFuzzTest, MutatedAsciiTokensAndBytes) {
  fuzzAscii(31337u, 1500, true);
}

}  // namespace
}  // namespace dentsim
