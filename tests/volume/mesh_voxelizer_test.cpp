// CPU reference voxelizer: analytic volumes, nesting, holes, watertight ties and hand-counted voxels.
#include "volume/mesh_voxelizer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_meshes.h"
#include "voxelize_support.h"
#include "volume/voxelize_layout.h"

namespace dentsim {
namespace {

using test::box;
using test::sphereVolume;

// Voxelizes layers on a grid of `level` fitted to their union; returns the volume.
BrickVolume voxelize(const std::vector<MeshLayer>& layers, int level, VolumeFrame* frame_out = nullptr,
                     VoxelizeOptions options = {}) {
  const RaySetup setup = test::raySetupFor(layers, level, options, frame_out);
  auto v = voxelizeCpu(setup, options);
  EXPECT_TRUE(v.ok());
  return std::move(v).value();
}

double volumeOf(const BrickVolume& v, const VolumeFrame& f, Material m) {
  return v.materialTotals().volumeMm3(m, f.voxel_mm);
}

TEST(GridFit, LevelLeavesTheMarginAndCentres) {
  Bounds3 b;
  b.add(Vec3d{0, 0, 0});
  b.add(Vec3d{10, 4, 20});
  auto f = fitGridToLevel(b, 5, 2);
  ASSERT_TRUE(f.ok());
  EXPECT_DOUBLE_EQ(f->voxel_mm, 20.0 / 28.0);  // 32 voxels minus 2 each side
  EXPECT_NEAR(f->origin_mm[2] + 2 * f->voxel_mm, 0.0, 1e-12);
  EXPECT_NEAR(f->origin_mm[0] + 16 * f->voxel_mm, 5.0, 1e-12);
  auto g = fitGridToVoxelSize(b, 0.1, 2);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->level, 8);  // 200 + 4 voxels need 256
  EXPECT_DOUBLE_EQ(g->voxel_mm, 0.1);
  EXPECT_FALSE(fitGridToVoxelSize(b, 1e-6, 2).ok());
  EXPECT_FALSE(fitGridToLevel(Bounds3{}, 7).ok());
}

TEST(RayCoverage, SharedEdgeAndVertexBelongToOneTriangle) {
  // A fan of triangles around a vertex that lies exactly on a ray centre, and shared edges that pass
  // through ray centres: every ray inside the fan's outline is covered exactly once.
  const float cx = 4.5f, cy = 4.5f;
  const float ring[6][2] = {{7.5f, 4.5f}, {6.5f, 7.5f}, {2.5f, 7.5f}, {1.5f, 4.5f}, {2.5f, 1.5f}, {6.5f, 1.5f}};
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      int covered = 0;
      for (int k = 0; k < 6; ++k) {
        float depth;
        uint32_t entering;
        const auto& a = ring[k];
        const auto& b = ring[(k + 1) % 6];
        covered += layout::voxRayHitsTriangle(cx, cy, 1, a[0], a[1], 1, b[0], b[1], 1, x + 0.5f, y + 0.5f, depth,
                                              entering);
      }
      // Inside the hexagon (strictly) every ray counts once; on its outline 0 or 1 times.
      EXPECT_LE(covered, 1) << x << "," << y;
      if (x == 4 && y == 4) {
        EXPECT_EQ(covered, 1);  // the shared vertex
      }
    }
}

TEST(MeshVoxelizer, HandCountedBoxes) {
  // Level 3 (8^3), margin 0: a box filling x,y in [2,6) voxels and z in [1, 4.5): columns inside
  // hold three full voxels and one half voxel, whose fill rounds 15.5 up to 16.
  TriangleMesh frame_box = box({0, 0, 0}, {8, 8, 8});
  TriangleMesh b = box({2, 2, 1}, {6, 6, 4.5});
  auto frame = fitGridToLevel(frame_box.bounds(), 3, 0);
  ASSERT_TRUE(frame.ok());
  ASSERT_DOUBLE_EQ(frame->voxel_mm, 1.0);
  auto setup = makeRaySetup({{Material::Dentin, &b, "box"}}, *frame, {});
  ASSERT_TRUE(setup.ok());
  auto v = voxelizeCpu(*setup, {});
  ASSERT_TRUE(v.ok());
  for (uint32_t z = 0; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x) {
        const bool in_xy = x >= 2 && x < 6 && y >= 2 && y < 6;
        Voxel want = 0;
        if (in_xy && z >= 1 && z < 4) want = makeVoxel(Material::Dentin, 31);
        if (in_xy && z == 4) want = makeVoxel(Material::Dentin, 16);
        EXPECT_EQ(v->voxel(x, y, z), want) << x << "," << y << "," << z;
      }
}

TEST(MeshVoxelizer, SphereWithinOnePercentAtLevel7) {
  const TriangleMesh s = test::uvSphere({1, 2, 3}, 5.0, 192, 96);
  VolumeFrame f;
  const BrickVolume v = voxelize({{Material::Enamel, &s, "sphere"}}, 7, &f);
  const double got = volumeOf(v, f, Material::Enamel);
  EXPECT_NEAR(got / sphereVolume(5.0), 1.0, 0.01);
  EXPECT_NEAR(got / s.signedVolume(), 1.0, 0.005);
  // Boundary voxels are partly filled: smooth surfaces, not a staircase.
  const auto totals = v.materialTotals();
  EXPECT_LT(totals.fill_sum[size_t(Material::Enamel)], 31u * totals.voxels[size_t(Material::Enamel)]);
}

TEST(MeshVoxelizer, TorusGenusOneWithinOnePercent) {
  const TriangleMesh t = test::torus({0, 0, 0}, 6.0, 2.0, 192, 64);
  VolumeFrame f;
  const BrickVolume v = voxelize({{Material::Dentin, &t, "torus"}}, 7, &f);
  EXPECT_NEAR(volumeOf(v, f, Material::Dentin) / test::torusVolume(6.0, 2.0), 1.0, 0.01);
  // The hole is empty: the centre column holds no tissue.
  const uint32_t c = 64;
  for (uint32_t z = 0; z < 128; ++z) EXPECT_EQ(v.voxel(c, c, z), 0) << z;
}

TEST(MeshVoxelizer, HollowBoxWithinOnePercent) {
  const TriangleMesh h = test::hollowBox({0.3, 0.1, 0.2}, {10.3, 8.1, 9.2}, 1.5);
  VolumeFrame f;
  const BrickVolume v = voxelize({{Material::Enamel, &h, "hollow box"}}, 7, &f);
  const double exact = 10.0 * 8.0 * 9.0 - 7.0 * 5.0 * 6.0;
  EXPECT_NEAR(volumeOf(v, f, Material::Enamel) / exact, 1.0, 0.01);
}

TEST(MeshVoxelizer, NestedLayersInnerWins) {
  const TriangleMesh outer = test::uvSphere({0, 0, 0}, 6.0);
  const TriangleMesh inner = test::uvSphere({0, 0, 0}, 3.0);
  VolumeFrame f;
  // Listed outer-first or inner-first, the pulp wins inside the enamel.
  for (bool swap : {false, true}) {
    std::vector<MeshLayer> layers{{Material::Enamel, &outer, "outer"}, {Material::Pulp, &inner, "inner"}};
    if (swap) std::swap(layers[0], layers[1]);
    const BrickVolume v = voxelize(layers, 7, &f);
    EXPECT_NEAR(volumeOf(v, f, Material::Pulp) / inner.signedVolume(), 1.0, 0.01);
    EXPECT_NEAR(volumeOf(v, f, Material::Enamel) / (outer.signedVolume() - inner.signedVolume()), 1.0, 0.01);
  }
}

TEST(MeshVoxelizer, InsideOutAndOverlappingShellsFill) {
  TriangleMesh s = test::uvSphere({0, 0, 0}, 4.0);
  const double expected = s.signedVolume();
  test::invertMesh(s);
  VolumeFrame f;
  BrickVolume v = voxelize({{Material::Dentin, &s, "inverted"}}, 7, &f);
  EXPECT_NEAR(volumeOf(v, f, Material::Dentin) / expected, 1.0, 0.01);

  // Two overlapping spheres in one layer: the union (lens formula), not the parity difference.
  TriangleMesh two = test::uvSphere({-2, 0, 0}, 4.0);
  test::appendMesh(two, test::uvSphere({2, 0, 0}, 4.0));
  v = voxelize({{Material::Dentin, &two, "two spheres"}}, 7, &f);
  const double r = 4.0, d = 4.0;
  const double lens = std::numbers::pi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12.0;
  EXPECT_NEAR(volumeOf(v, f, Material::Dentin) / (2 * expected - lens), 1.0, 0.01);
}

TEST(MeshVoxelizer, HolesBorrowFromBalancedNeighbours) {
  // Remove a cap of triangles at the north pole: rays through the hole see only the bottom.
  TriangleMesh open = test::uvSphere({0, 0, 0}, 5.0, 96, 48);
  const size_t cap = 96 * 3;  // the polar fan and two rings
  open.triangles.resize(open.triangles.size() - cap);
  const TriangleMesh closed = test::uvSphere({0, 0, 0}, 5.0, 96, 48);
  VolumeFrame f;
  VoxelizeOptions repair;
  const BrickVolume fixed = voxelize({{Material::Dentin, &open, "open"}}, 7, &f, repair);
  const double want = closed.signedVolume();
  const double got = volumeOf(fixed, f, Material::Dentin);
  EXPECT_NEAR(got / want, 1.0, 0.01);
  VoxelizeOptions none;
  none.hole_radius = 0;  // no donor: the layer is dropped on leaky rays, leaving a tunnel
  const BrickVolume tunnel = voxelize({{Material::Dentin, &open, "open"}}, 7, &f, none);
  const double dropped = volumeOf(tunnel, f, Material::Dentin);
  EXPECT_LT(dropped, 0.99 * want);
  EXPECT_LT(std::abs(got - want), std::abs(dropped - want));
}

TEST(MeshVoxelizer, RejectsBadSetups) {
  const TriangleMesh s = test::uvSphere({0, 0, 0}, 1.0);
  auto f = fitGridToLevel(s.bounds(), 5);
  ASSERT_TRUE(f.ok());
  EXPECT_FALSE(makeRaySetup({}, *f, {}).ok());
  EXPECT_FALSE(makeRaySetup({{Material::Empty, &s, "x"}}, *f, {}).ok());
  VoxelizeOptions bad;
  bad.subsamples = 5;
  EXPECT_FALSE(makeRaySetup({{Material::Dentin, &s, "x"}}, *f, bad).ok());
  TriangleMesh nan = s;
  nan.positions[3][1] = NAN;
  auto r = makeRaySetup({{Material::Dentin, &nan, "nan.stl"}}, *f, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("nan.stl"), std::string::npos);
}

}  // namespace
}  // namespace dentsim
