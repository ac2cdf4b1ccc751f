// GPU voxelizer against the CPU reference on small grids (lavapipe in CI), and against analytic volumes.
#include "gpu/gpu_voxelizer.h"

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "test_meshes.h"
#include "voxelize_support.h"

namespace dentsim::gpu::test {
namespace {

using dentsim::test::box;

// First voxel where the two volumes differ, or "" when they are equal. Brick by brick, so that a
// level-12 grid takes seconds, not the hours of 2^36 voxel reads.
std::string firstDifference(const BrickVolume& a, const BrickVolume& b) {
  if (a.level() != b.level()) return "levels differ";
  if (a == b) return "";
  const uint32_t bd = a.brickDim();
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        const BrickView ba = a.brick({bx, by, bz}), bb = b.brick({bx, by, bz});
        if (ba.uniform && bb.uniform && ba.value == bb.value) continue;
        for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
          const uint32_t x = bx * 8 + i % 8, y = by * 8 + i / 8 % 8, z = bz * 8 + i / 64;
          if (a.voxel(x, y, z) != b.voxel(x, y, z))
            return "voxel (" + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) + "): GPU " +
                   std::to_string(a.voxel(x, y, z)) + ", CPU " + std::to_string(b.voxel(x, y, z));
        }
      }
  return "";
}

class GpuVoxelizerTest : public GpuTest {
 protected:
  // Voxelizes on both and expects identical voxels; returns the GPU volume.
  BrickVolume both(const std::vector<MeshLayer>& layers, int level, VoxelizeOptions options = {},
                   VolumeFrame* frame_out = nullptr, VoxelizeTiming* timing_out = nullptr) {
    const RaySetup setup = dentsim::test::raySetupFor(layers, level, options, frame_out);
    auto cpu = voxelizeCpu(setup, options);
    EXPECT_TRUE(cpu.ok());
    VoxelizeTiming timing;
    auto gpu = voxelizeGpu(ctx(), setup, options, &timing);
    EXPECT_TRUE(gpu.ok()) << (gpu ? "" : gpu.message());
    if (!gpu || !cpu) return BrickVolume(level);
    EXPECT_EQ(firstDifference(*gpu, *cpu), "");
    EXPECT_GT(timing.bands, 0u);
    EXPECT_EQ(gpu->stats().dense_bricks, timing.dense_bricks);
    if (timing_out) *timing_out = timing;
    return std::move(gpu).value();
  }
};

TEST_F(GpuVoxelizerTest, HandCountedBoxMatchesCpu) {
  TriangleMesh b = box({2, 2, 1}, {6, 6, 4.5});
  TriangleMesh frame_box = box({0, 0, 0}, {8, 8, 8});
  auto frame = fitGridToLevel(frame_box.bounds(), 3, 0);
  ASSERT_TRUE(frame.ok());
  auto setup = makeRaySetup({{Material::Dentin, &b, "box"}}, *frame, {});
  ASSERT_TRUE(setup.ok());
  auto gpu = voxelizeGpu(ctx(), *setup, {});
  ASSERT_TRUE(gpu.ok()) << gpu.message();
  EXPECT_EQ(gpu->voxel(3, 3, 2), makeVoxel(Material::Dentin, 31));
  EXPECT_EQ(gpu->voxel(3, 3, 4), makeVoxel(Material::Dentin, 16));
  EXPECT_EQ(gpu->voxel(1, 3, 2), 0);
  EXPECT_EQ(gpu->voxel(3, 3, 5), 0);
}

TEST_F(GpuVoxelizerTest, SphereTorusHollowBoxMatchCpuAndAnalytic) {
  VolumeFrame f;
  const TriangleMesh s = dentsim::test::uvSphere({1, 2, 3}, 5.0, 192, 96);
  BrickVolume v = both({{Material::Enamel, &s, "sphere"}}, 7, {}, &f);
  EXPECT_NEAR(v.materialTotals().volumeMm3(Material::Enamel, f.voxel_mm) / dentsim::test::sphereVolume(5.0), 1.0, 0.01);

  const TriangleMesh t = dentsim::test::torus({0, 0, 0}, 6.0, 2.0, 192, 64);
  v = both({{Material::Dentin, &t, "torus"}}, 7, {}, &f);
  EXPECT_NEAR(v.materialTotals().volumeMm3(Material::Dentin, f.voxel_mm) / dentsim::test::torusVolume(6.0, 2.0), 1.0,
              0.01);

  const TriangleMesh h = dentsim::test::hollowBox({0.3, 0.1, 0.2}, {10.3, 8.1, 9.2}, 1.5);
  v = both({{Material::Enamel, &h, "hollow box"}}, 7, {}, &f);
  EXPECT_NEAR(v.materialTotals().volumeMm3(Material::Enamel, f.voxel_mm) / (720.0 - 210.0), 1.0, 0.01);
}

TEST_F(GpuVoxelizerTest, NestedLayersAndSubsamplesMatchCpu) {
  const TriangleMesh outer = dentsim::test::uvSphere({0, 0, 0}, 6.0);
  const TriangleMesh mid = dentsim::test::uvSphere({0.5, 0, 0}, 4.0);
  const TriangleMesh inner = dentsim::test::torus({0.5, 0, 0}, 2.0, 0.7);
  const TriangleMesh lesion = dentsim::test::box({-1, -1, 3}, {1, 1, 7});
  const std::vector<MeshLayer> layers{{Material::Enamel, &outer, "enamel"},
                                      {Material::Dentin, &mid, "dentin"},
                                      {Material::Pulp, &inner, "pulp"},
                                      {Material::Caries, &lesion, "caries"}};
  for (int S : {1, 2, 3, 4}) {
    VoxelizeOptions o;
    o.subsamples = S;
    both(layers, 6, o);
  }
}

TEST_F(GpuVoxelizerTest, HoleRepairMatchesCpu) {
  TriangleMesh open = dentsim::test::uvSphere({0, 0, 0}, 5.0, 96, 48);
  open.triangles.resize(open.triangles.size() - 96 * 3);
  for (int radius : {0, 3, 8}) {
    VoxelizeOptions o;
    o.hole_radius = radius;
    both({{Material::Dentin, &open, "open"}}, 6, o);
  }
}

TEST_F(GpuVoxelizerTest, ManyChunksAndEmptyFootprint) {
  // Level 8 spans 4^3 chunks, so chunk tiles, packed blocks and their merge all take part.
  const TriangleMesh s = dentsim::test::uvSphere({0, 0, 0}, 5.0, 64, 32);
  const TriangleMesh small = dentsim::test::uvSphere({3.5, 3.5, 3.5}, 0.4, 16, 8);
  VolumeFrame f;
  BrickVolume v = both({{Material::Dentin, &s, "sphere"}, {Material::Caries, &small, "speck"}}, 8, {}, &f);
  const BrickStats st = v.stats();
  EXPECT_GT(st.uniform_chunks, 0u);
  EXPECT_GT(st.blocks, 0u);
}

TEST_F(GpuVoxelizerTest, BandsWithHaloAndPoolRegrowthMatchCpu) {
  // One chunk row per band, a hole whose rays borrow across band edges, and a pool that starts
  // with one brick and must grow.
  TriangleMesh open = dentsim::test::uvSphere({0, 0, 0}, 5.0, 96, 48);
  open.triangles.resize(open.triangles.size() - 96 * 3);
  const TriangleMesh inner = dentsim::test::torus({0, 0, 0}, 2.5, 1.0, 64, 24);
  VoxelizeOptions o;
  o.max_band_chunk_rows = 1;
  o.initial_brick_capacity = 1;
  VoxelizeTiming timing;
  both({{Material::Dentin, &open, "open"}, {Material::Pulp, &inner, "pulp"}}, 8, o, nullptr, &timing);
  EXPECT_EQ(timing.bands, 4u);  // level 8 has four chunk rows
}

TEST_F(GpuVoxelizerTest, LargeTrianglesStayWithinLavapipesLoopBudget) {
  // A flat box at level 10 with one ray per voxel: each of its big faces' triangles covers about
  // 400 000 rays. lavapipe stops every loop of an invocation after 65 535 iterations in all, so
  // when one invocation took a whole triangle, the rays past that point got no hit and the box
  // came out with holes. Tiles of rays keep each invocation small; the volume must equal the CPU's.
  const TriangleMesh slab = box({0, 0, 0}, {10, 9.3, 1.7});
  VoxelizeOptions o;
  o.subsamples = 1;
  VolumeFrame f;
  const BrickVolume v = both({{Material::Enamel, &slab, "slab"}}, 10, o, &f);
  EXPECT_NEAR(v.materialTotals().volumeMm3(Material::Enamel, f.voxel_mm), 10 * 9.3 * 1.7, 0.01 * 10 * 9.3 * 1.7);
}

TEST_F(GpuVoxelizerTest, LongColumnsStayWithinLavapipesLoopBudget) {
  // A tall thin prism at level 12 with 4 x 4 rays per voxel: the columns along its sides are
  // painted in every one of their 512 bricks, far past lavapipe's 65 535 loop iterations for one
  // column; painted whole, their upper bricks held voxels with a fill but no tissue (voxel code 8,
  // as the CHAI3D tooth at level 12 showed). Segments of bricks keep each workgroup small.
  TriangleMesh prism = box({0, 0, 0}, {0.23, 0.19, 20});
  for (Vec3f& p : prism.positions) p[0] += 0.004f * p[2];  // a slight lean, so the walls cross columns
  VoxelizeOptions o;
  o.subsamples = 4;
  VolumeFrame f;
  const BrickVolume v = both({{Material::Dentin, &prism, "prism"}}, 12, o, &f);
  EXPECT_NEAR(v.materialTotals().volumeMm3(Material::Dentin, f.voxel_mm), 0.23 * 0.19 * 20, 0.02 * 0.23 * 0.19 * 20);
}

TEST_F(GpuVoxelizerTest, TooManyRasterTilesAreRefusedBeforeAllocating) {
  // 24 copies of a flat box at level 12 with 4 x 4 rays per voxel: the footprint of each top and
  // bottom triangle spans the whole 16384^2-ray grid, 262 144 tiles of 8 bytes, and their 96
  // triangles together need 192 MiB, more than one 128 MiB storage binding. The tiles are counted
  // before any is stored, so the refusal costs nothing.
  const TriangleMesh one = box({0, 0, 0}, {10, 10, 0.5});
  TriangleMesh pile;
  for (int i = 0; i < 24; ++i) dentsim::test::appendMesh(pile, one);
  VoxelizeOptions o;
  o.subsamples = 4;
  const RaySetup setup = dentsim::test::raySetupFor({{Material::Dentin, &pile, "pile"}}, 12, o);
  if (ctx().limits().max_storage_buffer_range > (uint64_t{128} << 20))
    GTEST_SKIP() << "this device binds more than lavapipe's 128 MiB; the pile would fit";
  auto gpu = voxelizeGpu(ctx(), setup, o);
  ASSERT_FALSE(gpu.ok());
  EXPECT_NE(gpu.message().find("raster tiles exceed one storage binding"), std::string::npos) << gpu.message();
}

}  // namespace
}  // namespace dentsim::gpu::test
