// Tests of the instrument meshes: closed outward shells, bur sizes measured on the mesh, frames.
#include "model/tool_generator.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"

namespace dentsim {
namespace {

double radiusAboutZ(const Vec3f& p) { return std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1]); }

TEST(ToolGenerator, EveryToolIsClosedOutwardAndDeterministic) {
  for (const ToolSpec& t : toolCatalog()) {
    const TriangleMesh m = generateTool(t);
    const MeshTopology topo = analyzeTopology(m);
    EXPECT_EQ(topo.open_edges, 0u) << t.name;
    EXPECT_EQ(topo.nonmanifold_edges, 0u) << t.name;
    EXPECT_EQ(topo.flipped_edges, 0u) << t.name;
    EXPECT_EQ(topo.degenerate_triangles, 0u) << t.name;
    EXPECT_GT(topo.signed_volume_mm3, 0.0) << t.name;
    // Welded: no two vertices at one position (weldVertices would merge none).
    TriangleMesh welded = m;
    EXPECT_EQ(weldVertices(welded), 0u) << t.name;
    EXPECT_EQ(welded.vertexCount(), m.vertexCount()) << t.name;
    const TriangleMesh again = generateTool(t);
    EXPECT_EQ(again.positions, m.positions) << t.name;
  }
}

TEST(ToolGenerator, BurHeadsMatchTheirIsoSizes) {
  for (const ToolSpec& t : toolCatalog()) {
    if (t.kind != ToolKind::RoundBur && t.kind != ToolKind::FissureBur) continue;
    const TriangleMesh m = generateTool(t);
    const Bounds3 b = m.bounds();
    EXPECT_NEAR(b.lo[2], 0.0, 1e-6) << t.name << ": cutting tip at the origin";
    EXPECT_NEAR(b.hi[2], 19.0, 1e-5) << t.name << ": FG bur length";
    double head = 0.0, shank = 0.0, head_top = 0.0;
    for (const Vec3f& p : m.positions) {
      const double r = radiusAboutZ(p);
      if (p[2] <= t.cutting_length_mm + 1e-4) head = std::max(head, r);
      if (p[2] > 10.0) shank = std::max(shank, r);
    }
    for (const Vec3f& p : m.positions)
      if (radiusAboutZ(p) >= 0.5 * t.head_diameter_mm - 1e-4 && p[2] < t.cutting_length_mm + 0.15) head_top = std::max(head_top, double(p[2]));
    EXPECT_NEAR(2.0 * head, t.head_diameter_mm, 1e-4) << t.name;
    EXPECT_NEAR(2.0 * shank, 1.6, 1e-4) << t.name << ": FG shank";
    // A round bur is widest at its equator, a fissure bur over its whole 4 mm head.
    const double widest_to = t.kind == ToolKind::RoundBur ? 0.5 * t.head_diameter_mm : t.cutting_length_mm;
    EXPECT_NEAR(head_top, widest_to, 1e-4) << t.name;
  }
}

TEST(ToolGenerator, HandpieceHoldsTheBurAxis) {
  const auto it = std::find_if(toolCatalog().begin(), toolCatalog().end(),
                               [](const ToolSpec& t) { return t.kind == ToolKind::Handpiece; });
  ASSERT_NE(it, toolCatalog().end());
  const TriangleMesh m = generateTool(*it);
  const Bounds3 b = m.bounds();
  // The head sits on the bur axis above the exposed bur; the body runs about 100 mm toward +x.
  EXPECT_GT(b.lo[2], 8.0);
  EXPECT_LT(b.lo[2], 10.0);
  EXPECT_NEAR(b.lo[0], -5.25, 1e-3);
  EXPECT_GT(b.hi[0], 95.0);
  EXPECT_NEAR(b.extent()[1], 12.0, 0.05) << "body diameter";
}

TEST(ToolGenerator, MirrorFacesPlusZAtTheOrigin) {
  const auto it = std::find_if(toolCatalog().begin(), toolCatalog().end(),
                               [](const ToolSpec& t) { return t.kind == ToolKind::Mirror; });
  ASSERT_NE(it, toolCatalog().end());
  const TriangleMesh m = generateTool(*it);
  EXPECT_LE(m.bounds().hi[2], 1e-6) << "nothing stands in front of the glass";
  // Triangles on the face plane z = 0 inside the rim point +z, and they cover the glass disc.
  double area = 0.0;
  for (const auto& t : m.triangles) {
    const Vec3f &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    if (a[2] != 0.0f || b[2] != 0.0f || c[2] != 0.0f) continue;
    const double nz = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]);
    EXPECT_GT(nz, 0.0);
    area += 0.5 * nz;
  }
  EXPECT_NEAR(area, 3.14159265 * 10.85 * 10.85, 0.01 * 3.14159265 * 10.85 * 10.85);
  EXPECT_NEAR(2.0 * std::max(-m.bounds().lo[1], m.bounds().hi[1]), 22.0, 1e-4) << "size 4 disc";
}

TEST(ToolGenerator, CatalogJsonListsEveryTool) {
  const std::string json = toolCatalogJson();
  for (const ToolSpec& t : toolCatalog()) {
    EXPECT_NE(json.find(std::string("\"file\": \"") + t.name + ".stl\""), std::string::npos) << t.name;
    EXPECT_NE(json.find(std::string("\"kind\": \"") + toolKindName(t.kind) + "\""), std::string::npos);
  }
}

}  // namespace
}  // namespace dentsim
