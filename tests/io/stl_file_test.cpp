// Tests of src/io/stl_file.cpp and src/io/mesh_units.cpp: topology of hand-made cubes, round trips, real teeth, and one-line errors.
#include "io/stl_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "io/mesh_units.h"
#include "test_support.h"

namespace dentsim {
namespace {

// ---- fixtures -------------------------------------------------------------------------------

// The unit cube [0,1]^3, corner i at (i&1, i>>1&1, i>>2&1), two counter-clockwise triangles per
// face seen from outside. 8 corners; 12 cube edges plus 6 face diagonals make 18 edges.
TriangleMesh unitCube() {
  TriangleMesh m;
  for (uint32_t i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float(i >> 1 & 1), float(i >> 2 & 1)});
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // z = 0, normal -z
                 {4, 5, 7}, {4, 7, 6},   // z = 1, +z
                 {0, 1, 5}, {0, 5, 4},   // y = 0, -y
                 {2, 6, 7}, {2, 7, 3},   // y = 1, +y
                 {0, 4, 6}, {0, 6, 2},   // x = 0, -x
                 {1, 3, 7}, {1, 7, 5}};  // x = 1, +x
  return m;
}

// Binary STL written field by field, independently of encodeStlBinary; every corner repeated, as
// in real files, and the normals left zero (the reader ignores them).
std::vector<uint8_t> binaryStl(const TriangleMesh& m, const std::string& header = "test") {
  std::vector<uint8_t> b(84 + 50 * m.triangleCount(), 0);
  std::memcpy(b.data(), header.data(), std::min<size_t>(header.size(), 80));
  const auto n = uint32_t(m.triangleCount());
  std::memcpy(b.data() + 80, &n, 4);
  for (size_t t = 0; t < m.triangleCount(); ++t)
    for (size_t k = 0; k < 3; ++k)
      std::memcpy(b.data() + 84 + 50 * t + 12 + 12 * k, m.positions[m.triangles[t][k]].data(), 12);
  return b;
}

std::vector<uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

// A single facet in ASCII with the given corner lines, for malformed-file tests.
const char* const kOneFacet =
    "solid tri\n"
    "  facet normal 0 0 1\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 1 0 0\n"
    "      vertex 0 1 0\n"
    "    endloop\n"
    "  endfacet\n"
    "endsolid tri\n";

Result<StlMesh> parse(const std::vector<uint8_t>& bytes, const StlReadLimits& limits = {}) {
  return parseStl(bytes, "enamel.stl", limits);
}
Result<StlMesh> parseText(const std::string& text, const StlReadLimits& limits = {}) {
  return parse(bytesOf(text), limits);
}

// One line, naming the file, and saying what went wrong.
void expectError(const Result<StlMesh>& r, const std::string& problem, const std::string& where = "enamel.stl") {
  ASSERT_FALSE(r.ok()) << "expected an error containing: " << problem;
  EXPECT_EQ(r.message().rfind(where + ": ", 0), 0u) << r.message();
  EXPECT_NE(r.message().find(problem), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

// ---- topology of the cube and its damaged variants ---------------------------------------------

TEST(StlFileTest, UnitCubeIsClosedOutwardWithVolumeOne) {
  Result<StlMesh> r = parse(binaryStl(unitCube()));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.format, StlFormat::Binary);
  EXPECT_EQ(r->info.file_triangles, 12u);
  EXPECT_EQ(r->info.dropped_triangles, 0u);
  EXPECT_EQ(r->mesh.vertexCount(), 8u);  // 36 corners welded to 8
  EXPECT_EQ(r->mesh.triangleCount(), 12u);
  const MeshTopology& topo = r->info.topology;
  EXPECT_EQ(topo.edges, 18u);
  EXPECT_EQ(topo.open_edges, 0u);
  EXPECT_EQ(topo.nonmanifold_edges, 0u);
  EXPECT_EQ(topo.flipped_edges, 0u);
  EXPECT_TRUE(topo.closed());
  EXPECT_EQ(topo.orientation(), "outward");
  EXPECT_EQ(topo.signed_volume_mm3, 1.0);  // exact: every term is a small dyadic number
}

TEST(StlFileTest, InsideOutCubeIsInwardWithVolumeMinusOne) {
  TriangleMesh m = unitCube();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  Result<StlMesh> r = parse(binaryStl(m));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->info.topology.closed());
  EXPECT_EQ(r->info.topology.orientation(), "inward");
  EXPECT_EQ(r->info.topology.signed_volume_mm3, -1.0);
}

TEST(StlFileTest, MissingTriangleLeavesThreeOpenEdges) {
  TriangleMesh m = unitCube();
  m.triangles.pop_back();
  Result<StlMesh> r = parse(binaryStl(m));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.topology.edges, 18u);
  EXPECT_EQ(r->info.topology.open_edges, 3u);  // the removed triangle's three edges now have one user
  EXPECT_FALSE(r->info.topology.closed());
}

TEST(StlFileTest, DuplicatedFaceMakesNonManifoldEdges) {
  TriangleMesh m = unitCube();
  m.triangles.push_back(m.triangles[0]);
  Result<StlMesh> r = parse(binaryStl(m));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.topology.nonmanifold_edges, 3u);  // each edge of the copy has three users
  EXPECT_FALSE(r->info.topology.closed());
}

TEST(StlFileTest, FlippedTriangleMakesFlippedEdges) {
  TriangleMesh m = unitCube();
  std::swap(m.triangles[4][1], m.triangles[4][2]);
  Result<StlMesh> r = parse(binaryStl(m));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->info.topology.closed());
  EXPECT_EQ(r->info.topology.flipped_edges, 3u);  // its edges run the same way as its neighbours'
  EXPECT_EQ(r->info.topology.orientation(), "inconsistent");
}

TEST(StlFileTest, CollapsedTrianglesAreDroppedAndCounted) {
  TriangleMesh m = unitCube();
  m.triangles.push_back({0, 0, 1});
  Result<StlMesh> r = parse(binaryStl(m));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.file_triangles, 13u);
  EXPECT_EQ(r->info.dropped_triangles, 1u);
  EXPECT_EQ(r->mesh.triangleCount(), 12u);
  EXPECT_TRUE(r->info.topology.closed());
}

// ---- writers and round trips --------------------------------------------------------------

// The cube under a shear and an offset (still closed and outward), with coordinates that short
// decimals cannot hold exactly.
TriangleMesh awkwardCube() {
  TriangleMesh m = unitCube();
  const float offset[3] = {1234.567f, -0.3f, 1e-3f};
  for (size_t i = 0; i < m.positions.size(); ++i)
    for (size_t a = 0; a < 3; ++a) m.positions[i][a] = m.positions[i][a] * 0.1f + float(i) / 3.0f + offset[a];
  return m;
}

// The same triangles in the same order with bit-identical corners; the indices may differ, as the
// reader numbers corners in the order of first use.
void expectSameSurface(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.triangleCount(), b.triangleCount());
  for (size_t t = 0; t < a.triangleCount(); ++t)
    for (size_t k = 0; k < 3; ++k)
      EXPECT_EQ(std::memcmp(a.positions[a.triangles[t][k]].data(), b.positions[b.triangles[t][k]].data(), 12), 0)
          << "triangle " << t << " corner " << k;
}

TEST(StlFileTest, BinaryAndAsciiRoundTripsAreBitExact) {
  const TriangleMesh m = awkwardCube();
  Result<StlMesh> bin = parse(encodeStlBinary(m, "awkward"));
  Result<StlMesh> txt = parseText(encodeStlAscii(m, "awkward"));
  ASSERT_TRUE(bin.ok()) << bin.message();
  ASSERT_TRUE(txt.ok()) << txt.message();
  EXPECT_EQ(bin->info.format, StlFormat::Binary);
  EXPECT_EQ(txt->info.format, StlFormat::Ascii);
  EXPECT_EQ(bin->info.solid_name, "awkward");
  EXPECT_EQ(txt->info.solid_name, "awkward");
  EXPECT_EQ(bin->mesh.vertexCount(), 8u);
  expectSameSurface(bin->mesh, m);
  expectSameSurface(txt->mesh, m);
  EXPECT_EQ(bin->mesh.positions, txt->mesh.positions);
  EXPECT_EQ(bin->mesh.triangles, txt->mesh.triangles);
  EXPECT_EQ(txt->info.topology.orientation(), "outward");
}

TEST(StlFileTest, WritersComputeUnitNormalsFromTheCorners) {
  TriangleMesh m = unitCube();
  m.positions.push_back({5, 5, 5});
  m.triangles.push_back({8, 8, 8});  // no area: zero normal
  const std::vector<uint8_t> b = encodeStlBinary(m, "");
  ASSERT_EQ(b.size(), 84u + 50u * 13u);
  float n[3];
  std::memcpy(n, b.data() + 84, 12);  // triangle 0 lies in z = 0, wound to face -z
  EXPECT_EQ(n[0], 0.0f);
  EXPECT_EQ(n[1], 0.0f);
  EXPECT_EQ(n[2], -1.0f);
  std::memcpy(n, b.data() + 84 + 50 * 2, 12);  // z = 1
  EXPECT_EQ(n[2], 1.0f);
  std::memcpy(n, b.data() + 84 + 50 * 12, 12);
  EXPECT_EQ(n[0], 0.0f);
  EXPECT_EQ(n[1], 0.0f);
  EXPECT_EQ(n[2], 0.0f);

  const std::string text = encodeStlAscii(m, "cube");
  EXPECT_EQ(text.rfind("solid cube\n", 0), 0u);
  EXPECT_NE(text.find("facet normal 0 0 -1\n"), std::string::npos);
  EXPECT_NE(text.find("facet normal 1 0 0\n"), std::string::npos);
  EXPECT_NE(text.find("facet normal 0 0 0\n"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 14), "endsolid cube\n");
}

TEST(StlFileTest, BinaryHeaderStartingWithSolidIsReadAsBinary) {
  const std::vector<uint8_t> b = encodeStlBinary(unitCube(), "solid cube exported by a CAD program");
  ASSERT_EQ(std::memcmp(b.data(), "solid", 5), 0);
  Result<StlMesh> r = parse(b);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.format, StlFormat::Binary);
  EXPECT_EQ(r->info.solid_name, "solid cube exported by a CAD program");
  EXPECT_EQ(r->mesh.triangleCount(), 12u);
}

TEST(StlFileTest, HeaderTextIsTrimmedOfNulsAndSpaces) {
  Result<StlMesh> r = parse(encodeStlBinary(unitCube(), "  molar 36  "));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.solid_name, "molar 36");
  std::string long_header(100, 'x');
  const std::vector<uint8_t> b = encodeStlBinary(unitCube(), long_header);
  ASSERT_EQ(b.size(), 84u + 50u * 12u);  // cut to 80 bytes
  Result<StlMesh> cut = parse(b);
  ASSERT_TRUE(cut.ok()) << cut.message();
  EXPECT_EQ(cut->info.solid_name, std::string(80, 'x'));
}

TEST(StlFileTest, WriteStlAndReadStlThroughAFile) {
  test::TempDir dir;
  const std::string path = dir.file("cube.stl");
  ASSERT_TRUE(writeStl(path, awkwardCube(), "dentsim").ok());
  Result<StlMesh> r = readStl(path);
  ASSERT_TRUE(r.ok()) << r.message();
  expectSameSurface(r->mesh, awkwardCube());
  EXPECT_TRUE(std::filesystem::is_regular_file(path));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporary left

  expectError(readStl(dir.file("missing.stl")), "cannot open", dir.file("missing.stl"));
}

// ---- ASCII tolerance ------------------------------------------------------------------------

TEST(StlFileTest, AsciiToleratesWhatRealFilesDo) {
  // CRLF, tabs, upper case, no name after solid, a different name after endsolid, a '+' sign, an
  // exponent, a normal that points the wrong way, a facet without a normal, trailing blank lines.
  const std::string text =
      "SOLID\r\n"
      "\tFacet Normal 0 0 -1\r\n"
      "\t\tOUTER LOOP\r\n"
      "\t\t\tVERTEX 0 0 0\r\n"
      "\t\t\tVERTEX +1.0E+00 0 0\r\n"
      "\t\t\tVERTEX 0 1e0 0\r\n"
      "\t\tENDLOOP\r\n"
      "\tENDFACET\r\n"
      "  facet outer loop vertex 0 0 0 vertex 0 1 0 vertex 0 0 1 endloop endfacet\r\n"
      "endsolid some_other_name\r\n"
      "\r\n\r\n   \n";
  Result<StlMesh> r = parseText(text);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.format, StlFormat::Ascii);
  EXPECT_EQ(r->info.solid_name, "");
  EXPECT_EQ(r->info.file_triangles, 2u);
  EXPECT_EQ(r->mesh.vertexCount(), 4u);
  ASSERT_EQ(r->mesh.triangleCount(), 2u);
  // The corners keep their file order: the stated normal (-z) does not turn the triangle over.
  EXPECT_EQ(r->mesh.positions[r->mesh.triangles[0][1]], (Vec3f{1, 0, 0}));
  EXPECT_EQ(r->mesh.positions[r->mesh.triangles[0][2]], (Vec3f{0, 1, 0}));
}

TEST(StlFileTest, AsciiAcceptsNanNormalsAndSeveralSolids) {
  std::string text = kOneFacet;
  text.replace(text.find("normal 0 0 1"), 12, "normal -nan nan inf");
  text += "solid second\nfacet normal 0 0 0 outer loop vertex 5 5 5 vertex 6 5 5 vertex 5 6 5 endloop endfacet\n"
          "endsolid\n";
  Result<StlMesh> r = parseText(text);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.solid_name, "tri");
  EXPECT_EQ(r->info.file_triangles, 2u);
}

TEST(StlFileTest, AsciiAcceptsPaddingAfterTheLastEndsolid) {
  Result<StlMesh> r = parseText(kOneFacet + std::string("\0\0\0\x1a", 4));
  ASSERT_TRUE(r.ok()) << r.message();
  expectError(parseText(kOneFacet + std::string("\0\0x", 3)), "line 10: binary data (byte 0x00) in an ASCII STL");
}

TEST(StlFileTest, AsciiLeadingWhitespaceBeforeSolid) {
  Result<StlMesh> r = parseText(std::string("\n\n  \t") + kOneFacet);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.solid_name, "tri");
}

// ---- malformed ASCII ------------------------------------------------------------------------

// kOneFacet with `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = kOneFacet;
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(StlFileTest, AsciiErrorsNameTheLineAndTheProblem) {
  expectError(parseText(edited("endsolid tri\n", "bogus\nendsolid tri\n")), "line 9: expected \"facet\" or \"endsolid\", found \"bogus\"");
  expectError(parseText(edited("      vertex 0 1 0\n", "      vertex 0 1 0\n      vertex 1 1 0\n")),
              "line 7: facet starting on line 2 has more than 3 vertices");
  expectError(parseText(edited("      vertex 0 1 0\n", "")), "line 6: facet starting on line 2 has 2 vertices, expected 3");
  expectError(parseText(edited("    endloop\n", "")), "line 7: missing endloop");
  expectError(parseText(edited("  endfacet\n", "")), "line 8: missing endfacet");
  expectError(parseText(edited("endsolid tri\n", "")), "line 9: missing endsolid");
  expectError(parseText(edited("vertex 1 0 0", "vertex 1 0.0.0 0")), "line 5: expected a number, found \"0.0.0\"");
  expectError(parseText(edited("vertex 1 0 0", "vertex 1 0")), "line 6: expected a number, found \"vertex\"");
  expectError(parseText(edited("vertex 1 0 0", "vertex 1 1e39 0")), "line 5: number \"1e39\" is out of the 32-bit float range");
  expectError(parseText(edited("vertex 1 0 0", "vertex 1 nan 0")), "line 5: vertex has a non-finite coordinate \"nan\"");
  expectError(parseText(edited("vertex 1 0 0", "vertex 1 -inf 0")), "line 5: vertex has a non-finite coordinate");
  expectError(parseText(edited("outer loop", "outer")), "line 4: expected \"loop\" after \"outer\", found \"vertex\"");
  expectError(parseText(edited("normal 0 0 1", "normal 0 0 x")), "line 2: expected a number, found \"x\"");
  expectError(parseText(edited("endsolid tri\n", "endsolid tri\ntrailing words\n")), "line 10: unexpected \"trailing\" after endsolid");
  expectError(parseText("solid empty\nendsolid empty\n"), "ASCII STL with no facets");
  expectError(parseText("solid"), "line 1: missing endsolid");
}

TEST(StlFileTest, AsciiWithBinaryBlobIsRejected) {
  std::string text = "solid x\n  facet normal 0 0 1\n";
  text += std::string("\x00\x01\x02\x03garbage", 11);
  expectError(parseText(text), "line 3: binary data (byte 0x00) in an ASCII STL");
  // Text whose first 84 bytes are clean gets no guess about a binary reading.
  const Result<StlMesh> stray = parseText(edited("endloop", "endloop \x01"));
  expectError(stray, "line 7: binary data (byte 0x01) in an ASCII STL");
  EXPECT_EQ(stray.message().find("header says"), std::string::npos) << stray.message();
}

TEST(StlFileTest, TruncatedBinaryWithSolidHeaderMentionsTheSize) {
  std::vector<uint8_t> b = encodeStlBinary(unitCube(), "solid cube");
  b.resize(b.size() - 7);
  // It starts with "solid", so it is read as text and fails on the header's NULs; the error
  // also gives what the binary reading would have said.
  expectError(parse(b), "binary STL header says 12 triangles (684 bytes) but the file has 677 bytes (truncated?)");
  expectError(parse(b), "line 1: binary data");
}

// ---- malformed binary -----------------------------------------------------------------------

TEST(StlFileTest, BinaryNanAndInfNameTheTriangle) {
  std::vector<uint8_t> b = binaryStl(unitCube());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + 84 + 50 * 5 + 12 + 12 * 2 + 4, &nan, 4);
  expectError(parse(b), "triangle 5, corner 2 has a non-finite coordinate (NaN)");
  b = binaryStl(unitCube());
  const float inf = -std::numeric_limits<float>::infinity();
  std::memcpy(b.data() + 84 + 50 * 11 + 12, &inf, 4);
  expectError(parse(b), "triangle 11, corner 0 has a non-finite coordinate (Inf)");
}

TEST(StlFileTest, BinaryNormalsAreIgnoredEvenWhenNan) {
  std::vector<uint8_t> b = binaryStl(unitCube());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t t = 0; t < 12; ++t) std::memcpy(b.data() + 84 + 50 * t, &nan, 4);
  Result<StlMesh> r = parse(b);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.topology.orientation(), "outward");
}

TEST(StlFileTest, BinarySizeAndCountErrors) {
  const std::vector<uint8_t> good = binaryStl(unitCube());
  std::vector<uint8_t> zero(84, 0);
  expectError(parse(zero), "binary STL with no triangles");

  std::vector<uint8_t> cut(good.begin(), good.end() - 10);
  expectError(parse(cut), "binary STL header says 12 triangles (684 bytes) but the file has 674 bytes (truncated?)");

  std::vector<uint8_t> big = good;
  const uint32_t count = 1000;
  std::memcpy(big.data() + 80, &count, 4);
  expectError(parse(big), "binary STL header says 1000 triangles (50084 bytes) but the file has 684 bytes (truncated?)");

  std::vector<uint8_t> longer = good;
  longer.resize(good.size() + 3);
  expectError(parse(longer), "(trailing data?)");

  const uint32_t huge = 0xffffffffu;
  std::memcpy(big.data() + 80, &huge, 4);
  expectError(parse(big), "says 4294967295 triangles (214748364834 bytes)");

  expectError(parse({}), "empty file, not an STL");
  expectError(parseText("hello"), "not an STL file: 5 bytes is shorter than a binary STL header");
}

TEST(StlFileTest, TriangleLimitIsCheckedBeforeAllocating) {
  StlReadLimits small;
  small.max_triangles = 10;
  expectError(parse(binaryStl(unitCube()), small), "12 triangles exceed the limit of 10 triangles: mesh too large for the memory budget");
  expectError(parseText(encodeStlAscii(unitCube(), "c"), small), "more than 10 triangles exceed the limit of 10 triangles");
  small.max_triangles = 12;
  EXPECT_TRUE(parse(binaryStl(unitCube()), small).ok());
  EXPECT_TRUE(parseText(encodeStlAscii(unitCube(), "c"), small).ok());
}

TEST(StlFileTest, AllTrianglesDegenerateIsAnError) {
  TriangleMesh m;
  m.positions = {{1, 2, 3}};
  m.triangles = {{0, 0, 0}, {0, 0, 0}};
  expectError(parse(binaryStl(m)), "all 2 triangles are degenerate");
}

// ---- real teeth -----------------------------------------------------------------------------

TEST(StlFileTest, RealTeethAreClosedAndOutward) {
  const std::filesystem::path dir = test::dataDir() / "teeth";
  if (test::dataDir().empty() || !std::filesystem::is_directory(dir))
    GTEST_SKIP() << "real data not found (../shared/data/teeth or $DENTSIM_DATA_DIR)";
  struct Expected {
    const char* name;
    uint64_t triangles;  // from the data README
  };
  for (const Expected& e : {Expected{"chai3d_molar_tooth.stl", 3072}, Expected{"chai3d_molar_pulp.stl", 5696},
                            Expected{"cc0_molar_wikimedia.stl", 24576}, Expected{"rlzoo_dental_bur.stl", 3120},
                            Expected{"chai3d_round_bur.stl", 886}}) {
    const std::string path = (dir / e.name).string();
    Result<StlMesh> r = readStl(path);
    ASSERT_TRUE(r.ok()) << r.message();
    const StlInfo& info = r->info;
    EXPECT_EQ(info.format, StlFormat::Binary) << e.name;
    EXPECT_EQ(info.file_triangles, e.triangles) << e.name;
    EXPECT_TRUE(info.topology.closed()) << e.name << ": " << info.topology.open_edges << " open, "
                                        << info.topology.nonmanifold_edges << " non-manifold edges";
    EXPECT_EQ(info.topology.orientation(), "outward") << e.name;
    std::printf("  %-24s %6llu triangles, %6zu vertices, %llu dropped, volume %.6g units^3, extent %.4g, header \"%s\"\n",
                e.name, static_cast<unsigned long long>(info.file_triangles), r->mesh.vertexCount(),
                static_cast<unsigned long long>(info.dropped_triangles), info.topology.signed_volume_mm3,
                r->mesh.bounds().maxExtent(), info.solid_name.c_str());
  }

  // The CHAI3D molar is unitless; x0.04 gives about 9.3 x 11.7 x 20.1 mm.
  Result<StlMesh> molar = readStl((dir / "chai3d_molar_tooth.stl").string());
  ASSERT_TRUE(molar.ok()) << molar.message();
  const double volume_mm3 = molar->info.topology.signed_volume_mm3 * 0.04 * 0.04 * 0.04;
  std::printf("  chai3d_molar_tooth at x0.04: %.1f mm^3\n", volume_mm3);
  EXPECT_GT(volume_mm3, 200.0);   // a molar is several hundred mm^3
  EXPECT_LT(volume_mm3, 2000.0);  // and less than its 9.3 x 11.7 x 20.1 mm box (2187 mm^3)
  // Read raw, its size warns and suggests a scale; scaled, it is a tooth.
  EXPECT_NE(toothExtentWarning(molar->mesh.bounds(), "molar.stl").find("does not look like a tooth"), std::string::npos);
  molar->mesh.scale(0.04);
  EXPECT_EQ(toothExtentWarning(molar->mesh.bounds(), "molar.stl"), "");

  Result<StlMesh> bur = readStl((dir / "rlzoo_dental_bur.stl").string());
  ASSERT_TRUE(bur.ok()) << bur.message();
  EXPECT_EQ(toothExtentWarning(bur->mesh.bounds(), "bur.stl"), "");  // already in mm
}

// ---- units ----------------------------------------------------------------------------------

TEST(MeshUnitsTest, ParsesTheUnitNames) {
  LengthUnit u = LengthUnit::Metre;
  ASSERT_TRUE(parseLengthUnit("mm", &u));
  EXPECT_EQ(u, LengthUnit::Millimetre);
  ASSERT_TRUE(parseLengthUnit("cm", &u));
  EXPECT_EQ(u, LengthUnit::Centimetre);
  ASSERT_TRUE(parseLengthUnit("m", &u));
  EXPECT_EQ(u, LengthUnit::Metre);
  ASSERT_TRUE(parseLengthUnit("um", &u));
  EXPECT_EQ(u, LengthUnit::Micrometre);
  u = LengthUnit::Metre;
  ASSERT_TRUE(parseLengthUnit("\xC2\xB5m", &u));  // micro sign
  EXPECT_EQ(u, LengthUnit::Micrometre);
  u = LengthUnit::Metre;
  ASSERT_TRUE(parseLengthUnit("\xCE\xBCm", &u));  // Greek mu
  EXPECT_EQ(u, LengthUnit::Micrometre);
  for (const char* bad : {"", "MM", "mm ", "km", "in", "micron", "u"}) {
    u = LengthUnit::Centimetre;
    EXPECT_FALSE(parseLengthUnit(bad, &u)) << bad;
    EXPECT_EQ(u, LengthUnit::Centimetre) << bad;
  }
  EXPECT_EQ(millimetresPer(LengthUnit::Millimetre), 1.0);
  EXPECT_EQ(millimetresPer(LengthUnit::Centimetre), 10.0);
  EXPECT_EQ(millimetresPer(LengthUnit::Metre), 1000.0);
  EXPECT_EQ(millimetresPer(LengthUnit::Micrometre), 0.001);
  for (LengthUnit unit : {LengthUnit::Millimetre, LengthUnit::Centimetre, LengthUnit::Metre, LengthUnit::Micrometre}) {
    LengthUnit back = LengthUnit::Millimetre;
    ASSERT_TRUE(parseLengthUnit(lengthUnitSymbol(unit), &back));
    EXPECT_EQ(back, unit);
  }
}

// Bounds from the origin to (x, x/2, x/3), so the largest extent is x.
Bounds3 box(double x) {
  Bounds3 b;
  b.add(Vec3d{0, 0, 0});
  b.add(Vec3d{x, x / 2, x / 3});
  return b;
}

TEST(MeshUnitsTest, ExtentWarningThresholds) {
  EXPECT_EQ(toothExtentWarning(box(20.0), "enamel.stl"), "");
  EXPECT_EQ(toothExtentWarning(box(2.0), "enamel.stl"), "");    // a small bur head
  EXPECT_EQ(toothExtentWarning(box(150.0), "enamel.stl"), "");  // a handpiece

  const std::string tiny = toothExtentWarning(box(0.0011), "enamel.stl");
  EXPECT_EQ(tiny.rfind("enamel.stl: extent 0.0011 mm does not look like a tooth", 0), 0u) << tiny;
  EXPECT_NE(tiny.find("check --units or --scale"), std::string::npos) << tiny;
  EXPECT_EQ(tiny.find("--units m"), std::string::npos) << tiny;  // x1000 gives 1.1 mm: still no tooth

  const std::string metres = toothExtentWarning(box(0.011), "enamel.stl");
  EXPECT_NE(metres.find("as metres it would be 11 mm: --units m"), std::string::npos) << metres;
  const std::string cm = toothExtentWarning(box(1.5), "enamel.stl");
  EXPECT_NE(cm.find("as centimetres it would be 15 mm: --units cm"), std::string::npos) << cm;
  const std::string um = toothExtentWarning(box(9000.0), "enamel.stl");
  EXPECT_NE(um.find("as micrometres it would be 9 mm: --units um"), std::string::npos) << um;
  const std::string tenths = toothExtentWarning(box(500.0), "enamel.stl");
  EXPECT_NE(tenths.find("--scale 0.1"), std::string::npos) << tenths;
  const std::string huge = toothExtentWarning(box(1e7), "enamel.stl");
  EXPECT_NE(huge.find("does not look like a tooth"), std::string::npos) << huge;
  EXPECT_EQ(huge.find(": --"), std::string::npos) << huge;  // no factor fits

  const std::string empty = toothExtentWarning(Bounds3{}, "enamel.stl");
  EXPECT_NE(empty.find("extent 0 mm"), std::string::npos) << empty;
  for (const std::string& w : {tiny, metres, cm, um, tenths, huge, empty})
    EXPECT_EQ(w.find('\n'), std::string::npos) << w;
}

}  // namespace
}  // namespace dentsim
