// Tool meshes for drawing: creased per-corner normals on a cube and a smooth fan, and the glass disc.
#include "render/tool_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dentsim::render::test {
namespace {

// A unit cube, 8 welded vertices and 12 outward triangles.
TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float(i >> 1 & 1), float(i >> 2 & 1)});
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

TEST(ToolMesh, CubeCornersKeepTheirFaceNormals) {
  const TriangleMesh m = cube();
  const auto v = creasedVertices(m, 40.0);
  // Three corners per triangle; every edge is a 90-degree crease, so each corner takes its own
  // face's normal, which is an outward axis direction.
  ASSERT_EQ(v.size(), 36u);
  for (size_t t = 0; t < 12; ++t) {
    const ToolVertex& a = v[3 * t];
    for (size_t k = 1; k < 3; ++k) {
      EXPECT_FLOAT_EQ(v[3 * t + k].nx, a.nx);
      EXPECT_FLOAT_EQ(v[3 * t + k].ny, a.ny);
      EXPECT_FLOAT_EQ(v[3 * t + k].nz, a.nz);
    }
    EXPECT_FLOAT_EQ(std::fabs(a.nx) + std::fabs(a.ny) + std::fabs(a.nz), 1.0f);
    // Outward: the normal points from the cube's centre toward the face.
    const float cx = (v[3 * t].px + v[3 * t + 1].px + v[3 * t + 2].px) / 3 - 0.5f;
    const float cy = (v[3 * t].py + v[3 * t + 1].py + v[3 * t + 2].py) / 3 - 0.5f;
    const float cz = (v[3 * t].pz + v[3 * t + 1].pz + v[3 * t + 2].pz) / 3 - 0.5f;
    EXPECT_GT(a.nx * cx + a.ny * cy + a.nz * cz, 0.0f);
  }
}

TEST(ToolMesh, CubeWithWideCreaseAveragesThreeFaces) {
  // At 100 degrees no cube edge is a crease: a corner averages the (equal-area) faces around its
  // vertex, two triangles of one face and one or two of each other face, weighted by area.
  const auto v = creasedVertices(cube(), 100.0);
  for (const ToolVertex& c : v) {
    const float len = std::sqrt(c.nx * c.nx + c.ny * c.ny + c.nz * c.nz);
    EXPECT_NEAR(len, 1.0f, 1e-6f);
    // Every component is non-zero and points away from the centre.
    EXPECT_GT(c.nx * (c.px - 0.5f), 0.0f);
    EXPECT_GT(c.ny * (c.py - 0.5f), 0.0f);
    EXPECT_GT(c.nz * (c.pz - 0.5f), 0.0f);
  }
}

TEST(ToolMesh, DiscIsAFanFacingPlusZ) {
  const auto v = discVertices(2.0, 0.5, 8);
  ASSERT_EQ(v.size(), 24u);
  for (size_t t = 0; t < 8; ++t) {
    const ToolVertex &a = v[3 * t], &b = v[3 * t + 1], &c = v[3 * t + 2];
    EXPECT_EQ(a.px, 0.0f);
    EXPECT_EQ(a.py, 0.0f);
    EXPECT_NEAR(std::hypot(b.px, b.py), 2.0f, 1e-6f);
    EXPECT_EQ(b.pz, 0.5f);
    EXPECT_EQ(c.nz, 1.0f);
    // Counter-clockwise seen from +Z: the fan triangle's z cross product is positive.
    EXPECT_GT((b.px - a.px) * (c.py - a.py) - (b.py - a.py) * (c.px - a.px), 0.0f);
  }
}

}  // namespace
}  // namespace dentsim::render::test
