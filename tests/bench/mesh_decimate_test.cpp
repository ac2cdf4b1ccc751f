// Tests of decimateMesh: triangle counts near the target, volume kept, a closed result, determinism.
#include "bench/mesh_decimate.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace dentsim::bench {
namespace {

TEST(MeshDecimateTest, SphereAtAQuarterKeepsCountVolumeAndClosure) {
  const TriangleMesh sphere = test::uvSphere({0, 0, 0}, 5.0, 100, 101);  // 2 x 100 x 100 = 20,000 triangles
  ASSERT_EQ(sphere.triangleCount(), 20000u);
  ASSERT_TRUE(analyzeTopology(sphere).closed());
  DecimateInfo info;
  const TriangleMesh q = decimateMesh(sphere, 0.25, &info);
  EXPECT_EQ(info.input_triangles, 20000u);
  EXPECT_EQ(info.target_triangles, 5000u);
  EXPECT_EQ(info.output_triangles, q.triangleCount());
  EXPECT_NEAR(double(q.triangleCount()), 5000.0, 500.0);
  EXPECT_NEAR(q.signedVolume(), sphere.signedVolume(), 0.01 * sphere.signedVolume());
  EXPECT_EQ(info.method, "simplify");
  EXPECT_TRUE(info.topology.closed()) << info.topology.open_edges << " open edges";
  EXPECT_TRUE(info.topology.consistent());
  EXPECT_LE(q.vertexCount(), sphere.vertexCount() / 2);  // unused vertices are dropped
}

TEST(MeshDecimateTest, SameInputGivesSameOutput) {
  const TriangleMesh sphere = test::uvSphere({0, 0, 0}, 2.0, 40, 41);
  const TriangleMesh a = decimateMesh(sphere, 0.12);
  const TriangleMesh b = decimateMesh(sphere, 0.12);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.positions, b.positions);
}

TEST(MeshDecimateTest, FractionOneIsACopy) {
  const TriangleMesh sphere = test::uvSphere({0, 0, 0}, 1.0, 8, 5);  // 2 x 8 x 4 = 64 triangles
  DecimateInfo info;
  const TriangleMesh same = decimateMesh(sphere, 1.0, &info);
  EXPECT_EQ(info.method, "copy");
  EXPECT_EQ(same.triangles, sphere.triangles);
  EXPECT_EQ(info.output_triangles, 64u);
}

TEST(MeshDecimateTest, SmallFractionsStillReachTheCount) {
  const TriangleMesh sphere = test::uvSphere({0, 0, 0}, 5.0, 100, 101);
  for (double f : {0.06, 0.12, 0.5}) {
    DecimateInfo info;
    const TriangleMesh d = decimateMesh(sphere, f, &info);
    EXPECT_LE(double(d.triangleCount()), 1.05 * f * 20000.0) << f << " " << info.method;
    EXPECT_GE(double(d.triangleCount()), 0.8 * f * 20000.0) << f << " " << info.method;
    EXPECT_NEAR(d.signedVolume(), sphere.signedVolume(), 0.05 * sphere.signedVolume()) << f;
  }
}

TEST(MeshDecimateTest, TetrahedronHasNoTriangleToSpare) {
  // 4 vertices, 4 triangles: any collapse leaves a flat, degenerate surface, and clustering to 2
  // triangles erases it, so asking for half keeps all 4, closed.
  TriangleMesh tet;
  tet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  DecimateInfo info;
  const TriangleMesh d = decimateMesh(tet, 0.5, &info);
  EXPECT_EQ(info.target_triangles, 2u);
  EXPECT_EQ(d.triangleCount(), 4u);
  EXPECT_EQ(info.method, "simplify");
  EXPECT_TRUE(info.topology.closed());
  EXPECT_NEAR(d.signedVolume(), 1.0 / 6.0, 1e-7);
}

}  // namespace
}  // namespace dentsim::bench
