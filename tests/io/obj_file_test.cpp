// Tests of src/io/obj_file.cpp: a cube in every corner notation, fans, negative indices, each malformed line named, and mutated files that never crash.
#include "io/obj_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "test_support.h"

namespace dentsim {
namespace {

std::span<const uint8_t> bytesOf(const std::string& text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

// A unit cube: eight vertices and six quads, counter-clockwise from outside.
const std::string kCube =
    "# a cube\n"
    "mtllib cube.mtl\n"
    "o cube\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1 1.0\n"
    "vt 0 0\nvn 0 0 1\n"
    "g sides\nusemtl bone\ns off\n"
    "f 1 4 3 2\n"
    "f 5/1 6/1 7/1 8/1\n"
    "f 1//1 2//1 6//1 5//1\r\n"
    "f 2/1/1 3/1/1 7/1/1 6/1/1\n"
    "f -5 -8 -4 -1   # 4 1 5 8, counted back from the last vertex\n"
    "f +3 +4 +8 +7\n";

TEST(ObjFile, ACubeInEveryCornerNotationIsTwelveTrianglesOfVolumeOne) {
  Result<ObjMesh> r = parseObj(bytesOf(kCube), "cube.obj");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->mesh.vertexCount(), 8u);
  EXPECT_EQ(r->mesh.triangleCount(), 12u);
  EXPECT_EQ(r->file_faces, 6u);
  EXPECT_EQ(r->polygon_faces, 6u);
  EXPECT_NEAR(r->mesh.signedVolume(), 1.0, 1e-9);
  // The fan of the first face: (0, 3, 2) and (0, 2, 1) in 0-based indices.
  EXPECT_EQ(r->mesh.triangles[0], (std::array<uint32_t, 3>{0, 3, 2}));
  EXPECT_EQ(r->mesh.triangles[1], (std::array<uint32_t, 3>{0, 2, 1}));
  // "f -5 -8 -4 -1" after eight vertices is 4 1 5 8.
  EXPECT_EQ(r->mesh.triangles[8], (std::array<uint32_t, 3>{3, 0, 4}));
}

TEST(ObjFile, AFileIsReadFromDisk) {
  test::TempDir dir;
  test::writeBytes(dir.file("c.obj"), std::vector<uint8_t>(kCube.begin(), kCube.end()));
  Result<ObjMesh> r = readObj(dir.file("c.obj"));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->mesh.triangleCount(), 12u);
  EXPECT_EQ(readObj(dir.file("missing.obj")).message().rfind(dir.file("missing.obj"), 0), 0u);
}

TEST(ObjFile, EachMalformedLineIsOneErrorNamingTheLine) {
  struct Case {
    std::string text, message;
  };
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const Case cases[] = {
      {"v 0 0\n", "t.obj: line 1: vertex coordinate \"\" is not a finite number"},
      {"v 0 nan 0\n", "t.obj: line 1: vertex coordinate \"nan\" is not a finite number"},
      {"v 0 1e39 0\n", "t.obj: line 1: vertex coordinate \"1e39\" is not a finite number"},
      {"v 0 0x10 0\n", "t.obj: line 1: vertex coordinate \"0x10\" is not a finite number"},
      {tri + "f 1 2\n", "t.obj: line 4: a face needs three corners, this one has 2"},
      {tri + "f 1 2 0\n", "t.obj: line 4: face corner \"0\" is not a vertex index (1, 2, ... or -1, -2, ...)"},
      {tri + "f 1 2 x\n", "t.obj: line 4: face corner \"x\" is not a vertex index (1, 2, ... or -1, -2, ...)"},
      {tri + "f 1 2 -4\n", "t.obj: line 4: face corner \"-4\" reaches before the first vertex"},
      {tri + "f 1 2 4\n", "t.obj: line 4: face corner 4 is beyond the 3 vertices of the file"},
      {tri + "f 1 2 99999999999999999999\n", "t.obj: line 4: face corner \"99999999999999999999\" is not a vertex index (1, 2, ... or -1, -2, ...)"},
      {tri, "t.obj: no faces: an OBJ surface needs `f` lines"},
      {"", "t.obj: no faces: an OBJ surface needs `f` lines"},
      {std::string("v 0 0 0\n\0\n", 10), "t.obj: not an OBJ text file (it holds NUL bytes)"},
  };
  for (const Case& c : cases) {
    Result<ObjMesh> r = parseObj(bytesOf(c.text), "t.obj");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_EQ(r.message(), c.message);
  }
}

TEST(ObjFile, CountsOverTheLimitsAreRefusedBeforeStoring) {
  ObjReadLimits limits;
  limits.max_vertices = 7;
  EXPECT_EQ(parseObj(bytesOf(kCube), "c.obj", limits).message(), "c.obj: line 11: more than 7 vertices");
  limits = {};
  limits.max_triangles = 11;
  EXPECT_EQ(parseObj(bytesOf(kCube), "c.obj", limits).message(), "c.obj: line 22: more than 11 triangles");
}

// Bytes flipped, dropped and repeated at random: every result is a mesh whose indices are in range,
// or one line naming the source.
TEST(ObjFile, MutatedFilesGiveAMeshInRangeOrOneLine) {
  std::mt19937 rng(42);
  for (int round = 0; round < 3000; ++round) {
    std::string text = kCube;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0: text[at] = char(rng() % 256); break;
        case 1: text.erase(at, 1 + rng() % 8); break;
        default: text.insert(at, text.substr(at, 1 + rng() % 16)); break;
      }
    }
    Result<ObjMesh> r = parseObj(bytesOf(text), "m.obj");
    if (r.ok()) {
      for (const auto& t : r->mesh.triangles)
        for (uint32_t i : t) ASSERT_LT(i, r->mesh.vertexCount());
      EXPECT_FALSE(r->mesh.triangles.empty());
    } else {
      EXPECT_EQ(r.message().rfind("m.obj: ", 0), 0u) << r.message();
      EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
    }
  }
}

}  // namespace
}  // namespace dentsim
