// Bounded, deterministic mutation fuzzing of the OBJ reader: hostile text never crashes it, an accepted mesh is sound, and every failure is one line.
#include "io/obj_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

// A small closed mesh in most of the forms exporters write: comments, groups, normals and texture
// coordinates (skipped), a quad split into a fan, slashed corners and a negative index.
const char kSeed[] =
    "# a tetrahedron and a quad\n"
    "o tooth\ng crown\nusemtl enamel\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1 1.0\nv 1 1 1\n"
    "vt 0.5 0.5\nvn 0 0 1\ns off\n"
    "f 1 3 2\nf 1/1 2/1 4/1\nf 2//1 3//1 4//1\nf -5 -2 -3\nf 2 5 4 3\n";

// An OBJ-specific mutation: a statement the reader must treat with care.
void mutateObj(std::vector<uint8_t>& bytes, std::mt19937& rng) {
  static const char* kLines[] = {"f 0 1 2\n",     "f 1 2\n",          "f 99999999999999999999 1 2\n",
                                 "v nan 0 0\n",   "v 1e400 0 0\n",    "f -9 1 2\n",
                                 "f 1/ 2// 3\n",  "v 1 2\n",          "f 1 2 3 4 5 6 7 8 9 10 11 12\n",
                                 "f a b c\n",     "v 0x1p3 0 0\n",    "\x1b[31mv 1 1 1\n"};
  const std::string line = kLines[test::pick(rng, std::size(kLines))];
  const size_t at = test::pick(rng, bytes.size() + 1);
  bytes.insert(bytes.begin() + std::ptrdiff_t(at), line.begin(), line.end());
}

TEST(ObjFuzz, HostileTextNeverCrashesAndEveryOutcomeIsSound) {
  const std::string where = "fuzz.obj";
  const std::vector<uint8_t> seed(kSeed, kSeed + sizeof kSeed - 1);
  {
    auto ok = parseObj(seed, where);
    ASSERT_TRUE(ok) << ok.message();
    ASSERT_EQ(ok->mesh.triangles.size(), 6u);  // four triangles and a quad as two
  }
  std::mt19937 rng(42);
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 4000; ++i) {
    std::vector<uint8_t> bytes = seed;
    for (int m = 0, n = 1 + int(rng() % 4); m < n; ++m)
      if (!test::mutateBytesGeneric(bytes, rng)) {
        if (rng() % 4 == 0) test::overwriteWithForeignMagic(bytes, rng);
        else mutateObj(bytes, rng);
      }
    const ObjReadLimits limits{64, 64};
    auto r = parseObj(bytes, where, limits);
    if (!r) {
      ++rejected;
      test::assertOneLineRejection(r.message(), where, i);
      ASSERT_EQ(r.message().find('\x1b'), std::string::npos) << "iteration " << i << ": raw control bytes in the message";
      continue;
    }
    ++accepted;
    const TriangleMesh& mesh = r->mesh;
    ASSERT_FALSE(mesh.triangles.empty()) << "iteration " << i;
    ASSERT_LE(mesh.positions.size(), limits.max_vertices) << "iteration " << i;
    ASSERT_LE(mesh.triangles.size(), limits.max_triangles) << "iteration " << i;
    for (const auto& p : mesh.positions)
      for (int a = 0; a < 3; ++a) ASSERT_TRUE(std::isfinite(p[a])) << "iteration " << i;
    for (const auto& t : mesh.triangles)
      for (int c = 0; c < 3; ++c) ASSERT_LT(t[c], mesh.positions.size()) << "iteration " << i;
  }
  // Both outcomes are exercised, or the fuzzing proves little.
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 100);
}

}  // namespace
}  // namespace dentsim
