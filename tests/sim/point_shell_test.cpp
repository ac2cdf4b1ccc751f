// PointShell: areas sum to the surface's, normals point in, the head is flagged, clusters partition the points.
#include "sim/point_shell.h"

#include <gtest/gtest.h>

#include <numbers>

#include "sim/tool_library.h"
#include "test_meshes.h"

namespace dentsim {
namespace {
using test::box;
using test::uvSphere;

TEST(PointShell, SphereShellCoversItsAreaWithInwardNormalsAtTheSpacing) {
  const double r = 0.5;
  const TriangleMesh sphere = uvSphere({0, 0, r}, r, 192, 96);
  PointShellOptions options;
  options.head_spacing_mm = 0.04;
  options.shank_spacing_mm = 0.04;
  options.cutting_length_mm = r;  // the lower half cuts
  auto shell = buildPointShell(sphere, options);
  ASSERT_TRUE(shell.ok()) << shell.message();
  // The mesh's own area (a little under 4 pi r^2), kept exactly by the binning.
  double mesh_area = 0;
  for (const auto& t : sphere.triangles) {
    const Vec3 a{sphere.positions[t[0]][0], sphere.positions[t[0]][1], sphere.positions[t[0]][2]};
    const Vec3 b{sphere.positions[t[1]][0], sphere.positions[t[1]][1], sphere.positions[t[1]][2]};
    const Vec3 c{sphere.positions[t[2]][0], sphere.positions[t[2]][1], sphere.positions[t[2]][2]};
    mesh_area += 0.5 * norm(cross(b - a, c - a));
  }
  EXPECT_NEAR(shell->total_area_mm2, mesh_area, 1e-9 * mesh_area);
  EXPECT_NEAR(mesh_area, 4 * std::numbers::pi * r * r, 0.002 * mesh_area);
  // About one point per spacing^2 of surface (cubes cut the sphere obliquely, so somewhat more).
  const double nominal = mesh_area / (0.04 * 0.04);
  EXPECT_GT(double(shell->size()), 0.8 * nominal);
  EXPECT_LT(double(shell->size()), 2.5 * nominal);
  const Vec3 centre{0, 0, r};
  size_t cutting = 0;
  for (size_t i = 0; i < shell->size(); ++i) {
    const Vec3 radial = normalized(shell->positions[i] - centre);
    EXPECT_LT(dot(shell->inward[i], radial), -0.99) << i;           // into the tool
    EXPECT_NEAR(norm(shell->positions[i] - centre), r, 0.002) << i;  // on the surface
    // Head cubes hold samples at or below the head's top only, shank cubes above it only.
    if (shell->cutting[i]) {
      EXPECT_LE(shell->positions[i].z, r) << i;
    } else {
      EXPECT_GT(shell->positions[i].z, r) << i;
    }
    cutting += shell->cutting[i];
  }
  EXPECT_EQ(cutting, shell->cuttingCount());
  EXPECT_GT(cutting, 0u);
  EXPECT_LT(cutting, shell->size());
  // Clusters tile the points in order, and their spheres hold them.
  uint32_t next = 0;
  for (const ShellCluster& c : shell->clusters) {
    EXPECT_EQ(c.first, next);
    next += c.count;
    for (uint32_t i = c.first; i < c.first + c.count; ++i)
      EXPECT_LE(norm(shell->positions[i] - c.centre), c.radius + 1e-12);
  }
  EXPECT_EQ(next, shell->size());
}

TEST(PointShell, HeadIsSampledFinerThanTheShank) {
  PointShellParams spacing;
  spacing.head_spacing_mm = 0.03;
  spacing.shank_spacing_mm = 0.12;
  auto bur = loadToolModel("fissure_bur_010", spacing);
  ASSERT_TRUE(bur.ok()) << bur.message();
  EXPECT_TRUE(bur->cuts);
  double head_area = 0, shank_area = 0;
  size_t head = 0, shank = 0;
  for (size_t i = 0; i < bur->shell.size(); ++i) {
    (bur->shell.cutting[i] ? head_area : shank_area) += bur->shell.area_mm2[i];
    (bur->shell.cutting[i] ? head : shank) += 1;
    if (bur->shell.cutting[i]) {
      EXPECT_LE(bur->shell.positions[i].z, 4.0 + 0.03);
    }
  }
  // Area per point follows spacing^2.
  EXPECT_LT(head_area / double(head), 0.5 * 0.03 * 0.03 * 4);
  EXPECT_GT(shank_area / double(shank), 4 * (head_area / double(head)));
}

TEST(PointShell, MirrorNeverCuts) {
  PointShellParams spacing;
  spacing.mirror_spacing_mm = 0.5;  // coarse: this checks flags, not density, and stays quick under ASan
  auto mirror = loadToolModel("mirror_size4", spacing);
  ASSERT_TRUE(mirror.ok()) << mirror.message();
  EXPECT_FALSE(mirror->cuts);
  EXPECT_EQ(mirror->shell.cuttingCount(), 0u);
  EXPECT_GT(mirror->shell.size(), 500u);
}

TEST(PointShell, BadInputIsAnErrorNotACrash) {
  PointShellOptions options;
  EXPECT_FALSE(buildPointShell(TriangleMesh{}, options).ok());
  TriangleMesh tiny = box({0, 0, 0}, {1, 1, 1});
  options.head_spacing_mm = 0;
  EXPECT_FALSE(buildPointShell(tiny, options).ok());
  options.head_spacing_mm = 1e-5;
  auto huge = buildPointShell(box({0, 0, 0}, {100, 100, 100}), options);
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.message().find("coarser spacing"), std::string::npos) << huge.message();
  EXPECT_FALSE(loadToolModel("turbine_handpiece", PointShellParams{}).ok());
  EXPECT_FALSE(loadToolModel("no_such_bur", PointShellParams{}).ok());
}

}  // namespace
}  // namespace dentsim
