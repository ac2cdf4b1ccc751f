// Tests of src/io/ply_file.cpp: exact round trips of a coloured cube, hand-written ASCII and binary files, fans, and one-line errors.
#include "io/ply_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/mesh_topology.h"
#include "test_support.h"

namespace dentsim {
namespace {

// ---- fixtures -------------------------------------------------------------------------------

// The unit cube [0,1]^3, corner i at (i&1, i>>1&1, i>>2&1), two counter-clockwise triangles per face
// seen from outside; each corner's normal points along its diagonal and its colour encodes its index,
// so that any reordering shows.
struct Cube {
  std::vector<Vec3f> positions, normals;
  std::vector<Rgb8> colours;
  std::vector<std::array<uint32_t, 3>> triangles;

  Cube() {
    const float d = 1.0f / std::sqrt(3.0f);
    for (uint32_t i = 0; i < 8; ++i) {
      positions.push_back({float(i & 1), float(i >> 1 & 1), float(i >> 2 & 1)});
      normals.push_back({(i & 1) ? d : -d, (i >> 1 & 1) ? d : -d, (i >> 2 & 1) ? d : -d});
      colours.push_back({uint8_t(i * 30), uint8_t(255 - i), uint8_t(i == 7 ? 255 : 0)});
    }
    triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  }
  PlyView view() const { return {positions, normals, colours, triangles}; }
};

std::vector<uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

Result<PlyMesh> parse(const std::vector<uint8_t>& bytes, const PlyReadLimits& limits = {}) {
  return parsePly(bytes, "crown.ply", limits);
}
Result<PlyMesh> parseText(const std::string& text, const PlyReadLimits& limits = {}) { return parse(bytesOf(text), limits); }

// One line, naming the file, and saying what went wrong.
void expectError(const Result<PlyMesh>& r, const std::string& problem) {
  ASSERT_FALSE(r.ok()) << "expected an error containing: " << problem;
  EXPECT_EQ(r.message().rfind("crown.ply: ", 0), 0u) << r.message();
  EXPECT_NE(r.message().find(problem), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

void expectSameCube(const PlyMesh& m, const Cube& c) {
  EXPECT_EQ(m.mesh.positions, c.positions);  // bit-exact: floats compare equal
  EXPECT_EQ(m.mesh.triangles, c.triangles);
  ASSERT_TRUE(m.normals.has_value());
  EXPECT_EQ(*m.normals, c.normals);
  ASSERT_TRUE(m.colours.has_value());
  EXPECT_EQ(*m.colours, c.colours);
}

// A header for `body`, with the cube's element counts unless given.
std::string asciiHeader(const std::string& vertex_props, size_t vertices, size_t faces) {
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertices) + "\n" + vertex_props +
         "element face " + std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}
const std::string kXyz = "property float x\nproperty float y\nproperty float z\n";

// One triangle in ASCII with the given vertex and face lines.
std::string asciiTriangle(const std::string& face = "3 0 1 2\n", const std::string& third = "0 1 0\n") {
  return asciiHeader(kXyz, 3, 1) + "0 0 0\n1 0 0\n" + third + face;
}

// ---- round trips ----------------------------------------------------------------------------

TEST(PlyFileTest, BinaryCubeRoundTripsExactly) {
  const Cube cube;
  const std::vector<uint8_t> bytes = encodePlyBinary(cube.view(), "unit cube");
  // The body is 8 vertices of 27 bytes (3+3 floats, 3 uchars) and 12 faces of 13 bytes (uchar, 3 ints).
  const std::string header(bytes.begin(), bytes.begin() + std::ptrdiff_t(bytes.size() - 8 * 27 - 12 * 13));
  EXPECT_EQ(header,
            "ply\nformat binary_little_endian 1.0\ncomment unit cube\nelement vertex 8\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            "element face 12\nproperty list uchar int vertex_indices\nend_header\n");
  // The last vertex record: corner 7 at (1,1,1), colour (210, 248, 255).
  const uint8_t* v7 = bytes.data() + header.size() + 7 * 27;
  float x = 0.0f;
  std::memcpy(&x, v7, 4);
  EXPECT_EQ(x, 1.0f);
  EXPECT_EQ(v7[24], 210);
  EXPECT_EQ(v7[25], 248);
  EXPECT_EQ(v7[26], 255);
  // The first face: count 3, then 0 2 3 as little-endian int32.
  const uint8_t* f0 = bytes.data() + header.size() + 8 * 27;
  EXPECT_EQ(f0[0], 3);
  int32_t idx[3];
  std::memcpy(idx, f0 + 1, 12);
  EXPECT_EQ(idx[0], 0);
  EXPECT_EQ(idx[1], 2);
  EXPECT_EQ(idx[2], 3);

  Result<PlyMesh> r = parse(bytes);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.format, PlyFormat::BinaryLittleEndian);
  EXPECT_EQ(r->info.file_faces, 12u);
  EXPECT_EQ(r->info.polygon_faces, 0u);
  expectSameCube(*r, cube);
  const MeshTopology topo = analyzeTopology(r->mesh);
  EXPECT_TRUE(topo.closed());
  EXPECT_TRUE(topo.consistent());
  EXPECT_DOUBLE_EQ(r->mesh.signedVolume(), 1.0);
}

TEST(PlyFileTest, AsciiCubeRoundTripsExactly) {
  Cube cube;
  // Values that need all nine significant digits to come back bit-exact.
  cube.positions[3] = {0.1f, 1.0f / 3.0f, -2.5e-7f};
  Result<PlyMesh> r = parse(bytesOf(encodePlyAscii(cube.view())));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->info.format, PlyFormat::Ascii);
  expectSameCube(*r, cube);
}

TEST(PlyFileTest, WritePlyIsReadBackFromDisk) {
  const Cube cube;
  const test::TempDir dir;
  const std::string path = dir.file("cube.ply");
  ASSERT_TRUE(writePly(path, cube.view(), "dentsim").ok());
  Result<PlyMesh> r = readPly(path);
  ASSERT_TRUE(r.ok()) << r.message();
  expectSameCube(*r, cube);
  // Only the file: no temporary left beside it.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()), 1);
}

TEST(PlyFileTest, OptionalPropertiesAreLeftOut) {
  const Cube cube;
  const PlyView geometry{cube.positions, {}, {}, cube.triangles};
  const std::vector<uint8_t> bytes = encodePlyBinary(geometry);
  const std::string text(bytes.begin(), bytes.end());
  EXPECT_EQ(text.find("nx"), std::string::npos);
  EXPECT_EQ(text.find("red"), std::string::npos);
  EXPECT_EQ(text.find("comment"), std::string::npos);
  Result<PlyMesh> r = parse(bytes);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r->normals.has_value());
  EXPECT_FALSE(r->colours.has_value());
  EXPECT_EQ(r->mesh.positions, cube.positions);

  // Colours without normals.
  const PlyView coloured{cube.positions, {}, cube.colours, cube.triangles};
  r = parse(encodePlyBinary(coloured));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r->normals.has_value());
  ASSERT_TRUE(r->colours.has_value());
  EXPECT_EQ(*r->colours, cube.colours);
}

TEST(PlyFileTest, WritePlyRefusesInconsistentViews) {
  const Cube cube;
  const test::TempDir dir;
  const std::string path = dir.file("bad.ply");
  const std::vector<Vec3f> few_normals(cube.normals.begin(), cube.normals.begin() + 3);
  Status s = writePly(path, PlyView{cube.positions, few_normals, {}, cube.triangles});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("3 normals for 8 vertices"), std::string::npos) << s.message();
  const std::vector<std::array<uint32_t, 3>> bad_index = {{0, 1, 8}};
  s = writePly(path, PlyView{cube.positions, {}, {}, bad_index});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("out of range"), std::string::npos) << s.message();
  EXPECT_FALSE(std::filesystem::exists(path));
}

// ---- files from other writers -----------------------------------------------------------------

// Double coordinates, properties in another order, CRLF lines, comments, obj_info, uint indices and
// a quad: read, and the quad split into the fan (0 1 2), (0 2 3).
TEST(PlyFileTest, ForeignBinaryLayoutIsRead) {
  const std::string header =
      "ply\r\nformat binary_little_endian 1.0\r\ncomment from elsewhere\r\nobj_info v1\r\nelement vertex 4\r\n"
      "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
      "property double x\r\nproperty double y\r\nproperty double z\r\n"
      "element face 1\r\nproperty list ushort uint vertex_index\r\nend_header\r\n";
  std::vector<uint8_t> b(header.begin(), header.end());
  const double corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int v = 0; v < 4; ++v) {
    b.push_back(uint8_t(v));
    b.push_back(10);
    b.push_back(20);
    for (double c : corners[v]) {
      uint8_t raw[8];
      std::memcpy(raw, &c, 8);
      b.insert(b.end(), raw, raw + 8);
    }
  }
  const uint16_t n = 4;
  const uint32_t quad[4] = {0, 1, 2, 3};
  b.insert(b.end(), reinterpret_cast<const uint8_t*>(&n), reinterpret_cast<const uint8_t*>(&n) + 2);
  b.insert(b.end(), reinterpret_cast<const uint8_t*>(quad), reinterpret_cast<const uint8_t*>(quad) + 16);

  Result<PlyMesh> r = parse(b);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->mesh.positions[2], (Vec3f{1, 1, 0}));
  ASSERT_TRUE(r->colours.has_value());
  EXPECT_EQ((*r->colours)[3], (Rgb8{3, 10, 20}));
  EXPECT_EQ(r->info.file_faces, 1u);
  EXPECT_EQ(r->info.polygon_faces, 1u);
  ASSERT_EQ(r->mesh.triangleCount(), 2u);
  EXPECT_EQ(r->mesh.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(r->mesh.triangles[1], (std::array<uint32_t, 3>{0, 2, 3}));
}

// A pentagon in ASCII gives three triangles; tokens may wrap across lines.
TEST(PlyFileTest, AsciiPolygonsBecomeFans) {
  const std::string text = asciiHeader(kXyz, 5, 1) + "0 0 0\n1 0 0\n2 1 0\n1 2 0 0 1 0\n5 0 1\n2 3 4\n";
  Result<PlyMesh> r = parseText(text);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->mesh.triangleCount(), 3u);
  EXPECT_EQ(r->mesh.triangles[2], (std::array<uint32_t, 3>{0, 3, 4}));
  EXPECT_EQ(r->mesh.positions[4], (Vec3f{0, 1, 0}));
}

TEST(PlyFileTest, EmptyMeshIsValid) {
  Result<PlyMesh> r = parseText(asciiHeader(kXyz, 0, 0));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->mesh.vertexCount(), 0u);
  EXPECT_EQ(r->mesh.triangleCount(), 0u);
}

// ---- bad files: one line naming the file and the problem ----------------------------------------

TEST(PlyFileTest, BadHeadersAreRefused) {
  const std::string tail = "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
  expectError(parseText(""), "empty file");
  expectError(parseText("solid cube\n"), "not a PLY file");
  expectError(parseText("ply"), "not a PLY file");
  expectError(parseText("ply\nformat binary_big_endian 1.0\n"), "big-endian");
  expectError(parseText("ply\nformat ascii 2.0\n"), "version");
  expectError(parseText("ply\nformat ascii 1.0\n"), "ends inside the header");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz + "element edge 0\n"), "unsupported element \"edge\"");
  expectError(parseText("ply\nformat ascii 1.0\nelement face 0\n"), "out of order");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex -1\n"), "bad count");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz + "property uchar alpha\n" + tail),
              "unsupported vertex property \"alpha\"");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz + "property float x\n" + tail), "appears twice");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\nproperty int x\nproperty float y\nproperty float z\n" + tail),
              "has type int, expected float or double");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\nproperty half x\n"), "unknown property type \"half\"");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n" + tail),
              "no vertex property \"z\"");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz + "property float nx\n" + tail), "nx, ny and nz");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz + "end_header\n"), "no face element");
  expectError(parseText("ply\nformat ascii 1.0\nelement vertex 0\n" + kXyz +
                        "element face 0\nproperty list uchar float vertex_indices\nend_header\n"),
              "not an integer type");
  expectError(parseText("ply\nformat ascii 1.0\nbogus\n"), "unexpected header line \"bogus\"");
  expectError(parseText("ply\nformat ascii 1.0\ncomment \x01\n"), "binary data in the header");
  expectError(parseText("ply\ncomment " + std::string(70000, 'x') + "\n"), "no end_header");
}

TEST(PlyFileTest, BadAsciiBodiesAreRefused) {
  expectError(parseText(asciiTriangle("3 0 1 3\n")), "face 0 has vertex index 3 out of range (3 vertices)");
  expectError(parseText(asciiTriangle("3 0 1 -1\n")), "vertex index -1 out of range");
  expectError(parseText(asciiTriangle("2 0 1 \n")), "face 0 has 2 corners, at least 3 needed");
  expectError(parseText(asciiTriangle("3 0 1 2\n", "0 nan 0\n")), "non-finite y (NaN)");
  expectError(parseText(asciiTriangle("3 0 1 2\n", "0 1e39 0\n")), "out of the float range");
  expectError(parseText(asciiTriangle("3 0 1 2\n", "0 one 0\n")), "line 12: vertex 2: expected a number for y");
  expectError(parseText(asciiTriangle("3 0 1 2 7\n")), "unexpected \"7\" after the last face");
  expectError(parseText(asciiTriangle("3 0 1      \n")), "ends inside face 0");  // padded past the size check
  expectError(parseText(asciiHeader(kXyz, 3, 1) + "0 0 0\n"), "truncated");
  const std::string rgb = kXyz + "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  expectError(parseText(asciiHeader(rgb, 3, 1) + "0 0 0 1 2 3\n1 0 0 4 5 6\n0 1 0 7 8 256\n3 0 1 2\n"),
              "expected a colour 0-255 for blue");
}

TEST(PlyFileTest, BadBinaryBodiesAreRefused) {
  const Cube cube;
  const std::vector<uint8_t> good = encodePlyBinary(cube.view());
  const size_t body = good.size() - 8 * 27 - 12 * 13;

  std::vector<uint8_t> b = good;
  b.pop_back();
  expectError(parse(b), "truncated");
  b = good;
  b.push_back(0);
  expectError(parse(b), "1 byte of trailing data");

  b = good;  // vertex 5's y: NaN
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + body + 5 * 27 + 4, &nan, 4);
  expectError(parse(b), "vertex 5 has a non-finite y (NaN)");

  b = good;  // vertex 2's nz: infinity
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(b.data() + body + 2 * 27 + 20, &inf, 4);
  expectError(parse(b), "vertex 2 has a non-finite nz (Inf)");

  b = good;  // face 4's last index: 8
  const int32_t eight = 8;
  std::memcpy(b.data() + body + 8 * 27 + 4 * 13 + 9, &eight, 4);
  expectError(parse(b), "face 4 has vertex index 8 out of range (8 vertices)");

  b = good;  // face 11's count: 2 (the body then has 4 bytes left over, but the count is caught first)
  b[body + 8 * 27 + 11 * 13] = 2;
  expectError(parse(b), "face 11 has 2 corners");

  b = good;  // face 11's count: 4, running off the end
  b[body + 8 * 27 + 11 * 13] = 4;
  expectError(parse(b), "truncated in face 11");
}

// Forged counts are refused from the header alone: nothing is allocated for them.
TEST(PlyFileTest, CountsBeyondTheBudgetOrTheFileAreRefused) {
  PlyReadLimits small;
  small.max_vertices = 4;
  small.max_triangles = 100;
  const Cube cube;
  expectError(parse(encodePlyBinary(cube.view()), small), "8 vertices exceed the limit of 4");
  small.max_vertices = 100;
  small.max_triangles = 6;
  expectError(parse(encodePlyBinary(cube.view()), small), "12 faces exceed the limit of 6");
  // Fans count against the triangle budget too: a pentagon is three triangles.
  small.max_triangles = 2;
  expectError(parseText(asciiHeader(kXyz, 5, 1) + "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n5 0 1 2 3 4\n", small),
              "more than 2 triangles after splitting polygons");

  const std::string forged = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n" + kXyz +
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expectError(parseText(forged), "exceed the limit");
  const std::string big = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000\n" + kXyz +
                          "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expectError(parseText(big + std::string(64, '\0')), "truncated: the header says 1000000 vertices and 1 faces");
  const std::string big_ascii = asciiHeader(kXyz, 1000000, 0);
  expectError(parseText(big_ascii + "0 0 0\n"), "truncated");
}

TEST(PlyFileTest, ReadPlyNamesTheFile) {
  const test::TempDir dir;
  const std::string path = dir.file("missing.ply");
  Result<PlyMesh> r = readPly(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(path + ": ", 0), 0u) << r.message();
  std::ofstream(dir.file("bad.ply")) << "ply\nformat ascii 1.0\n";
  r = readPly(dir.file("bad.ply"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(dir.file("bad.ply") + ": header line", 0), 0u) << r.message();
}

}  // namespace
}  // namespace dentsim
