// Tests of the instrument meshes: closed outward shells, bur sizes and tapers measured on the mesh, frames.
#include "model/tool_generator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"

namespace dentsim {
namespace {

double radiusAboutZ(const Vec3f& p) { return std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1]); }

const ToolSpec& tool(const char* name) {
  const ToolSpec* t = findTool(name);
  EXPECT_NE(t, nullptr) << name;
  return t ? *t : toolCatalog().front();
}

// The half-angle makers give for 856 and 847 diamonds.
const double kTan2 = std::tan(2.0 * std::numbers::pi / 180.0);
const double kSin2 = std::sin(2.0 * std::numbers::pi / 180.0);
const double kCos2 = std::cos(2.0 * std::numbers::pi / 180.0);

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

TEST(ToolGenerator, TaperedBursNarrowTwoDegreesFromTheirTop) {
  // widest diameter (ISO size / 10) and kind, as in the issue; 8 mm heads.
  const struct {
    const char* name;
    ToolKind kind;
    double top_mm;
  } burs[] = {{"chamfer_bur_016", ToolKind::ChamferBur, 1.6},
              {"chamfer_bur_018", ToolKind::ChamferBur, 1.8},
              {"shoulder_bur_014", ToolKind::ShoulderBur, 1.4},
              {"shoulder_bur_016", ToolKind::ShoulderBur, 1.6}};
  for (const auto& b : burs) {
    const ToolSpec& t = tool(b.name);
    EXPECT_EQ(t.kind, b.kind) << b.name;
    EXPECT_TRUE(isBur(t.kind)) << b.name;
    EXPECT_EQ(t.head_diameter_mm, b.top_mm) << b.name;
    EXPECT_EQ(t.cutting_length_mm, 8.0) << b.name;
    // 1.6 mm at the top, 1.6 - 2 * 8 tan 2 deg = 1.0413 mm carried down to the tip.
    const double tip = b.top_mm - 16.0 * kTan2;
    EXPECT_NEAR(t.tip_diameter_mm, tip, 1e-12) << b.name;
    EXPECT_NEAR(burRadiusAt(t, 8.0), 0.5 * b.top_mm, 1e-12) << b.name;
    EXPECT_NEAR(burRadiusAt(t, 1.0), 0.5 * tip + kTan2, 1e-12) << b.name;
    EXPECT_NEAR(burRadiusAt(t, 4.0), 0.5 * b.top_mm - 4.0 * kTan2, 1e-12) << b.name;
    EXPECT_EQ(burRadiusAt(t, 8.001), 0.0) << b.name << ": above the head";
    EXPECT_EQ(burRadiusAt(t, -0.001), 0.0) << b.name << ": below the tip";

    const TriangleMesh m = generateTool(t);
    const Bounds3 bounds = m.bounds();
    EXPECT_NEAR(bounds.lo[2], 0.0, 1e-6) << b.name << ": cutting tip at the origin";
    EXPECT_NEAR(bounds.hi[2], 19.0, 1e-5) << b.name << ": FG bur length";
    double head = 0.0, shank = 0.0, worst = 0.0;
    size_t on_cone = 0;
    for (const Vec3f& p : m.positions) {
      const double r = radiusAboutZ(p);
      if (p[2] > 10.0) shank = std::max(shank, r);
      if (p[2] > 8.0 + 1e-5) continue;
      head = std::max(head, r);
      if (r == 0.0) continue;  // the pole of a flat end stands inside the profile's end ring
      // Every ring of the head lies on the profile burRadiusAt describes.
      worst = std::max(worst, std::abs(r - burRadiusAt(t, std::min(double(p[2]), 8.0))));
      if (p[2] > 1.0 && std::abs(r - (0.5 * tip + p[2] * kTan2)) < 1e-5) ++on_cone;
    }
    EXPECT_NEAR(2.0 * head, b.top_mm, 1e-5) << b.name << ": widest at the top of the head";
    EXPECT_NEAR(2.0 * shank, 1.6, 1e-5) << b.name << ": FG shank";
    EXPECT_LT(worst, 1e-5) << b.name;
    EXPECT_GE(on_cone, 48u) << b.name << ": the top ring on the taper";
  }
}

TEST(ToolGenerator, ChamferBurEndsInASphereTangentToItsTaper) {
  const ToolSpec& t = tool("chamfer_bur_016");
  // A sphere resting on z = 0 (centre at height rho) at distance rho from the cone
  // r = a + z tan: rho = a cos / (1 - sin), meeting the cone at z = rho (1 - sin).
  const double a = 0.5 * (1.6 - 16.0 * kTan2);
  const double rho = a * kCos2 / (1.0 - kSin2);
  const double meet = rho * (1.0 - kSin2);
  EXPECT_NEAR(rho, 0.53913, 1e-5);
  const TriangleMesh m = generateTool(t);
  size_t at_tip = 0, on_sphere = 0;
  for (const Vec3f& p : m.positions) {
    if (p[2] == 0.0f) {
      ++at_tip;
      EXPECT_EQ(radiusAboutZ(p), 0.0) << "the end's pole";
    }
    if (p[2] > meet + 1e-6) continue;
    const double dz = double(p[2]) - rho, r = radiusAboutZ(p);
    EXPECT_NEAR(std::sqrt(r * r + dz * dz), rho, 1e-5) << p[2];
    ++on_sphere;
  }
  EXPECT_EQ(at_tip, 1u) << "a round end touches the tip plane in one point";
  EXPECT_GE(on_sphere, 1u + 48u * 12u);
  EXPECT_EQ(burRadiusAt(t, 0.0), 0.0);
  EXPECT_NEAR(burRadiusAt(t, meet), rho * kCos2, 1e-12) << "continuous where the arc meets the cone";
}

TEST(ToolGenerator, ShoulderBurEndsFlat) {
  const ToolSpec& t = tool("shoulder_bur_016");
  const double a = 0.5 * (1.6 - 16.0 * kTan2);
  const TriangleMesh m = generateTool(t);
  // The flat end: its centre and one whole ring at z = 0, the ring 0.05 mm fillet short of the
  // cone (its centre at a + e tan - e / cos from the axis).
  const double e = 0.05, rim = a + e * kTan2 - e / kCos2;
  size_t flat = 0;
  for (const Vec3f& p : m.positions) {
    if (p[2] != 0.0f) continue;
    ++flat;
    const double r = radiusAboutZ(p);
    if (r > 0.0) {
      EXPECT_NEAR(r, rim, 1e-6);
    }
  }
  EXPECT_EQ(flat, 1u + 48u);
  EXPECT_NEAR(burRadiusAt(t, 0.0), rim, 1e-12);
  EXPECT_GT(burRadiusAt(t, 0.0), 0.9 * a) << "a flat end, not a point";
  EXPECT_NEAR(burRadiusAt(t, 0.05), a + 0.05 * kTan2, 1e-12) << "on the cone 0.05 mm up";
  EXPECT_NEAR(burRadiusAt(t, 0.05), a, 0.002);
}

TEST(ToolGenerator, BurRadiusAtFollowsRoundAndFissureHeads) {
  const ToolSpec& round = tool("round_bur_010");
  EXPECT_EQ(round.tip_diameter_mm, round.head_diameter_mm);
  EXPECT_NEAR(burRadiusAt(round, 0.5), 0.5, 1e-12) << "equator";
  EXPECT_NEAR(burRadiusAt(round, 0.25), std::sqrt(0.1875), 1e-12);  // 0.5^2 - 0.25^2
  EXPECT_NEAR(burRadiusAt(round, 1.0), 0.0, 1e-12) << "top of the ball";
  EXPECT_EQ(burRadiusAt(round, 0.0), 0.0);
  const ToolSpec& fissure = tool("fissure_bur_012");
  EXPECT_EQ(fissure.tip_diameter_mm, fissure.head_diameter_mm);
  EXPECT_NEAR(burRadiusAt(fissure, 0.3), std::sqrt(0.36 - 0.09), 1e-12) << "in its rounded end";
  EXPECT_EQ(burRadiusAt(fissure, 0.6), 0.6);
  EXPECT_EQ(burRadiusAt(fissure, 4.0), 0.6);
  EXPECT_EQ(burRadiusAt(fissure, 4.1), 0.0);
  EXPECT_EQ(burRadiusAt(tool("mirror_size4"), 0.0), 0.0) << "not a bur";
  EXPECT_EQ(burRadiusAt(tool("turbine_handpiece"), 9.0), 0.0) << "not a bur";
}

TEST(ToolGenerator, FindToolAndIsBur) {
  ASSERT_NE(findTool("shoulder_bur_014"), nullptr);
  EXPECT_STREQ(findTool("shoulder_bur_014")->name, "shoulder_bur_014");
  EXPECT_EQ(findTool("shoulder_bur"), nullptr);
  EXPECT_EQ(findTool(""), nullptr);
  size_t burs = 0;
  for (const ToolSpec& t : toolCatalog()) burs += isBur(t.kind);
  EXPECT_EQ(burs, 4u + 3u + 2u + 2u) << "round, fissure, chamfer and shoulder burs";
  static_assert(isBur(ToolKind::ChamferBur) && isBur(ToolKind::ShoulderBur) && !isBur(ToolKind::Mirror) &&
                !isBur(ToolKind::Handpiece));
  EXPECT_STREQ(toolKindName(ToolKind::ChamferBur), "chamfer_bur");
  EXPECT_STREQ(toolKindName(ToolKind::ShoulderBur), "shoulder_bur");
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
  // Every bur states its tip: the tapered ones narrower than their head (1.6 - 16 tan 2 deg).
  EXPECT_NE(json.find(R"("name": "chamfer_bur_016", "file": "chamfer_bur_016.stl", "kind": "chamfer_bur", )"
                      R"("head_diameter_mm": 1.6, "tip_diameter_mm": 1.041, "cutting_length_mm": 8.0)"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(R"("name": "round_bur_010", "file": "round_bur_010.stl", "kind": "round_bur", )"
                      R"("head_diameter_mm": 1.0, "tip_diameter_mm": 1.000, "cutting_length_mm": 1.0)"),
            std::string::npos);
}

}  // namespace
}  // namespace dentsim
