// Bounded, deterministic mutation fuzzing of parsePly: hostile headers and bodies never crash it, and every failure is one clear line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "io/ply_file.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

const std::string kWhere = "fuzz.ply";

// A closed octahedron with normals and colours: 6 vertices, 8 triangles, so a case parses in microseconds.
struct Octahedron {
  std::vector<Vec3f> positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Vec3f> normals = positions;  // a unit octahedron's corner normals are its corners
  std::vector<Rgb8> colours = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {9, 9, 9}, {250, 240, 230}, {1, 2, 3}};
  std::vector<std::array<uint32_t, 3>> triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                    {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  PlyView view() const { return {positions, normals, colours, triangles}; }
};

// Tight, so that a forged count could not make a case allocate much even if a check failed.
PlyReadLimits fuzzLimits() {
  PlyReadLimits limits;
  limits.max_vertices = 4096;
  limits.max_triangles = 4096;
  return limits;
}

// Accepted meshes must be usable as they are; rejections must be one line naming the source.
void checkOutcome(const Result<PlyMesh>& r, int iteration, int* accepted, int* rejected) {
  if (r.ok()) {
    ++*accepted;
    const TriangleMesh& m = r->mesh;
    ASSERT_LE(m.vertexCount(), fuzzLimits().max_vertices) << "iteration " << iteration;
    ASSERT_LE(m.triangleCount(), fuzzLimits().max_triangles) << "iteration " << iteration;
    ASSERT_GE(m.triangleCount(), r->info.file_faces) << "iteration " << iteration;
    for (const auto& t : m.triangles)
      for (uint32_t c : t) ASSERT_LT(c, m.vertexCount()) << "iteration " << iteration;
    for (const Vec3f& p : m.positions)
      for (float v : p) ASSERT_TRUE(std::isfinite(v)) << "iteration " << iteration;
    if (r->normals) {
      ASSERT_EQ(r->normals->size(), m.vertexCount()) << "iteration " << iteration;
      for (const Vec3f& n : *r->normals)
        for (float v : n) ASSERT_TRUE(std::isfinite(v)) << "iteration " << iteration;
    }
    if (r->colours) {
      ASSERT_EQ(r->colours->size(), m.vertexCount()) << "iteration " << iteration;
    }
  } else {
    ++*rejected;
    test::assertOneLineRejection(r.message(), kWhere, iteration);
  }
}

using test::pick;

// Where the body starts, so that body mutations can aim past the header.
size_t bodyStart(const std::vector<uint8_t>& bytes) {
  static const std::string kEnd = "end_header\n";
  const auto it = std::search(bytes.begin(), bytes.end(), kEnd.begin(), kEnd.end());
  return it == bytes.end() ? 0 : size_t(it - bytes.begin()) + kEnd.size();
}

// One random byte-level change: flip a bit, write a boundary value, insert or delete a run, cut the
// tail, or write a non-finite float or an extreme integer into the body.
void mutateBytes(std::vector<uint8_t>& bytes, std::mt19937& rng) {
  if (test::mutateBytesGeneric(bytes, rng)) return;
  if (rng() % 8 == 0) return test::overwriteWithForeignMagic(bytes, rng);  // an STL, .nii.gz, .dvol ... as PLY
  // A 32-bit word in the body: NaN, infinities, huge, negative or out-of-range values.
  const size_t body = bodyStart(bytes);
  if (bytes.size() < body + 4) return;
  static const uint32_t kWords[] = {0x7fc00000u, 0x7f800000u, 0xff800000u, 0x7f7fffffu, 0xffffffffu,
                                    0x80000000u, 6u, 5u, 0x00000001u};
  const uint32_t w = kWords[rng() % std::size(kWords)];
  std::memcpy(bytes.data() + body + pick(rng, bytes.size() - body - 3), &w, 4);
}

// Splits text into lines, keeping each line's end, so that header lines can be swapped whole.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < text.size()) {
    const size_t nl = text.find('\n', start);
    const size_t end = nl == std::string::npos ? text.size() : nl + 1;
    out.push_back(text.substr(start, end - start));
    start = end;
  }
  return out;
}

// One random header-line change: drop, repeat or swap a line, or replace it with a tricky one.
void mutateHeaderLines(std::vector<std::string>& header, std::mt19937& rng) {
  static const std::vector<std::string> kLines = {
      "ply\n", "format ascii 1.0\n", "format binary_little_endian 1.0\n", "format binary_big_endian 1.0\n",
      "format ascii 1.1\n", "element vertex 0\n", "element vertex 4294967296\n", "element vertex 99999999999999999999\n",
      "element face 1\n", "element face 4097\n", "element edge 2\n", "element vertex -6\n",
      "property float x\n", "property double nz\n", "property uchar red\n", "property int y\n", "property uchar alpha\n",
      "property list uchar int vertex_indices\n", "property list int uint vertex_index\n",
      "property list uchar float vertex_indices\n", "property list char short vertex_indices\n",
      "comment x\n", "obj_info y\n", "end_header\n", "end_header extra\n", "\n", "\r\n", "property\n", "element\n",
  };
  const size_t i = pick(rng, header.size());
  switch (rng() % 4) {
    case 0: if (!header.empty()) header.erase(header.begin() + std::ptrdiff_t(i)); break;
    case 1: if (!header.empty()) header.insert(header.begin() + std::ptrdiff_t(i), header[pick(rng, header.size())]); break;
    case 2: if (header.size() > 1) std::swap(header[i], header[pick(rng, header.size())]); break;
    default: header.insert(header.begin() + std::ptrdiff_t(i), kLines[rng() % kLines.size()]); break;
  }
}

// One random token-level change in an ASCII body: a tricky number in place of one, or one dropped.
void mutateAsciiBody(std::string& body, std::mt19937& rng) {
  static const std::vector<std::string> kTokens = {
      "0", "-0", "1", "+1", "-1", "2", "3", "4", "5", "6", "255", "256", "1e38", "1e39", "-1e309", "1e-50",
      "1e-400", "nan", "-nan", "inf", "-inf", "0x10", "1.0.0", "--1", "+-1", "1e", ".", "+", "-", "4294967295",
      "9223372036854775808", "garbage", "\xc2\xb5", std::string(300, '9'),
  };
  std::vector<std::pair<size_t, size_t>> tokens;  // (start, length)
  for (size_t i = 0; i < body.size();) {
    while (i < body.size() && std::isspace(uint8_t(body[i]))) ++i;
    const size_t start = i;
    while (i < body.size() && !std::isspace(uint8_t(body[i]))) ++i;
    if (i > start) tokens.emplace_back(start, i - start);
  }
  if (tokens.empty()) return;
  const auto [start, length] = tokens[pick(rng, tokens.size())];
  if (rng() % 4 == 0) body.erase(start, length);
  else body.replace(start, length, kTokens[rng() % kTokens.size()]);
}

// Header and body fuzzing of one encoding; the header is mutated by lines in a third of the cases.
template <class Encode>
void fuzz(Encode encode, bool ascii, uint32_t seed, int iterations) {
  const std::vector<uint8_t> original = encode();
  const size_t body = bodyStart(original);
  ASSERT_GT(body, 0u);
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> bytes = original;
    const unsigned kind = rng() % 3;
    if (kind == 0) {
      std::vector<std::string> header = lines(std::string(original.begin(), original.begin() + std::ptrdiff_t(body)));
      const int edits = 1 + int(rng() % 2);
      for (int e = 0; e < edits; ++e) mutateHeaderLines(header, rng);
      std::string text;
      for (const std::string& l : header) text += l;
      bytes.assign(text.begin(), text.end());
      bytes.insert(bytes.end(), original.begin() + std::ptrdiff_t(body), original.end());
    } else if (kind == 1 && ascii) {
      std::string text(original.begin() + std::ptrdiff_t(body), original.end());
      const int edits = 1 + int(rng() % 2);
      for (int e = 0; e < edits; ++e) mutateAsciiBody(text, rng);
      bytes.assign(original.begin(), original.begin() + std::ptrdiff_t(body));
      bytes.insert(bytes.end(), text.begin(), text.end());
    } else {
      const int edits = 1 + int(rng() % 3);
      for (int e = 0; e < edits; ++e) mutateBytes(bytes, rng);
    }
    checkOutcome(parsePly(bytes, kWhere, fuzzLimits()), it, &accepted, &rejected);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(PlyFuzzTest, MutatedBinaryFiles) {
  const Octahedron o;
  fuzz([&] { return encodePlyBinary(o.view(), "octahedron"); }, false, 20240611u, 3000);
}

TEST(PlyFuzzTest, MutatedBinaryFilesWithoutOptionalProperties) {
  const Octahedron o;
  fuzz([&] { return encodePlyBinary(PlyView{o.positions, {}, {}, o.triangles}); }, false, 99u, 2000);
}

TEST(PlyFuzzTest, MutatedAsciiFiles) {
  const Octahedron o;
  fuzz([&] {
    const std::string text = encodePlyAscii(o.view(), "octahedron");
    return std::vector<uint8_t>(text.begin(), text.end());
  }, true, 7u, 3000);
}

}  // namespace
}  // namespace dentsim
