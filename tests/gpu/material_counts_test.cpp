// Tests of src/gpu/material_counts.cpp and compute/material_counts.comp.glsl: GPU totals equal BrickVolume::materialTotals().
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gpu/device_report.h"
#include "gpu/material_counts.h"
#include "gpu_fixture.h"

namespace dentsim::gpu::test {
namespace {

uint64_t cube(uint64_t n) { return n * n * n; }

uint64_t sum(const std::array<uint64_t, DS_MATERIAL_COUNT>& a) {
  uint64_t s = 0;
  for (uint64_t v : a) s += v;
  return s;
}

// A ball of enamel with a dentin core, partly filled at its surface, centred in the grid.
BrickVolume ballVolume(int level) {
  BrickVolume v(level);
  const double c = v.dim() / 2.0 - 0.5, r = v.dim() * 0.4;  // [voxels]
  for (uint32_t z = 0; z < v.dim(); ++z)
    for (uint32_t y = 0; y < v.dim(); ++y)
      for (uint32_t x = 0; x < v.dim(); ++x) {
        const double d = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
        if (d > r) continue;
        const Material m = d < r * 0.5 ? Material::Dentin : Material::Enamel;
        const uint32_t fill = d > r - 1.0 ? 1 + static_cast<uint32_t>((r - d) * 29.0) : DS_FILL_FULL;
        v.setVoxel(x, y, z, makeVoxel(m, fill));
      }
  return v;
}

}  // namespace

class MaterialCountsTest : public GpuTest {
 protected:
  // Counts `v` on the GPU and checks it equals the CPU reference and covers every voxel once.
  MaterialTotals expectGpuEqualsCpu(const BrickVolume& v, const CountOptions& options = {}, TimingOut* timing = nullptr) {
    const MaterialTotals cpu = v.materialTotals();
    auto gpu = countMaterialsGpu(ctx(), v, timing, options);
    EXPECT_TRUE(gpu) << gpu.message();
    if (!gpu) return {};
    EXPECT_TRUE(totalsEqual(*gpu, cpu)) << "level " << v.level();
    EXPECT_EQ(sum(gpu->voxels), cube(v.dim())) << "every voxel is counted exactly once";
    return *gpu;
  }
};

TEST_F(MaterialCountsTest, EmptyGridsCountOnlyEmptyVoxels) {
  for (int level : {3, 7}) {
    BrickVolume v(level);
    EXPECT_TRUE(v.blockWords().empty()) << "the empty-array binding path is exercised";
    const MaterialTotals t = expectGpuEqualsCpu(v);
    EXPECT_EQ(t.voxels[DS_MAT_EMPTY], cube(v.dim()));
    EXPECT_EQ(sum(t.fill_sum), 0u);
  }
}

TEST_F(MaterialCountsTest, OneDenseBrickWithMixedFills) {
  // Level 3 is one brick: 512 voxels cycling through all materials and fills.
  BrickVolume v(3);
  std::vector<Voxel> voxels(DS_BRICK_VOXELS);
  for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
    const uint32_t m = i % DS_TISSUE_COUNT;
    voxels[i] = makeVoxel(static_cast<Material>(m), 1 + (i * 7) % DS_FILL_FULL);
  }
  v.setBrick({0, 0, 0}, voxels.data());
  ASSERT_EQ(v.stats().dense_bricks, 1u);
  const MaterialTotals t = expectGpuEqualsCpu(v);
  // 512 = 6 * 85 + 2: materials 0 and 1 get 86 voxels, the others (neighbour included) 85.
  static_assert(DS_TISSUE_COUNT == 6, "the counts below are by hand for six codes");
  EXPECT_EQ(t.voxels[DS_MAT_EMPTY], 86u);
  EXPECT_EQ(t.voxels[DS_MAT_ENAMEL], 86u);
  EXPECT_EQ(t.voxels[DS_MAT_CARIES], 85u);
  EXPECT_EQ(t.voxels[DS_MAT_NEIGHBOUR], 85u);
  EXPECT_EQ(t.fill_sum[DS_MAT_EMPTY], 0u);
  EXPECT_GT(t.fill_sum[DS_MAT_PULP], 85u);
}

TEST_F(MaterialCountsTest, AllSolidGridIsUniformChunks) {
  BrickVolume v(7);  // 2^3 chunks
  for (uint32_t z = 0; z < v.brickDim(); ++z)
    for (uint32_t y = 0; y < v.brickDim(); ++y)
      for (uint32_t x = 0; x < v.brickDim(); ++x) v.setBrickUniform({x, y, z}, makeVoxel(Material::Dentin));
  v.compact();
  ASSERT_EQ(v.stats().uniform_chunks, v.stats().chunks) << "every chunk should be one tile";
  const MaterialTotals t = expectGpuEqualsCpu(v);
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], cube(128));
  EXPECT_EQ(t.fill_sum[DS_MAT_DENTIN], cube(128) * DS_FILL_FULL);
}

TEST_F(MaterialCountsTest, LevelsThreeToSeven) {
  // Levels 3..5 are smaller than a chunk: one chunk entry, a block with unused (empty) entries.
  for (int level = 3; level <= 7; ++level) {
    const BrickVolume v = ballVolume(level);
    const MaterialTotals t = expectGpuEqualsCpu(v);
    EXPECT_GT(t.voxels[DS_MAT_ENAMEL], 0u) << "level " << level;
  }
}

TEST_F(MaterialCountsTest, RandomVolumeWithFixedSeed) {
  BrickVolume v(6);
  std::mt19937 rng(20240611);
  auto below = [&](uint32_t n) { return static_cast<uint32_t>(rng() % n); };
  // Random voxels in random bricks, random whole-brick tiles elsewhere, then some voxels reset.
  for (int i = 0; i < 20000; ++i) {
    const uint32_t m = below(DS_TISSUE_COUNT);
    const uint32_t fill = 1 + below(DS_FILL_FULL);
    v.setVoxel(below(64), below(64), below(64), makeVoxel(static_cast<Material>(m), fill));
  }
  for (int i = 0; i < 40; ++i)
    v.setBrickUniform({below(8), below(8), below(8)}, makeVoxel(static_cast<Material>(1 + below(4)), 1 + below(31)));
  expectGpuEqualsCpu(v);  // with free slots in the pool
  v.compact();
  const BrickStats s = v.stats();
  EXPECT_GT(s.dense_bricks, 0u);
  EXPECT_GT(s.uniform_bricks, 0u);
  expectGpuEqualsCpu(v);
}

TEST_F(MaterialCountsTest, SeveralChunksSomeTiles) {
  BrickVolume v(8);  // 4^3 chunks
  // Chunk (0,0,0) all enamel (a chunk tile), chunk (1,0,0) one dense brick, chunk (3,3,3) a ball cut.
  for (uint32_t z = 0; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x) v.setBrickUniform({x, y, z}, makeVoxel(Material::Enamel));
  for (uint32_t i = 0; i < 64; ++i) v.setVoxel(64 + i, i, 3, makeVoxel(Material::Caries, 1 + i % 31));
  for (uint32_t z = 200; z < 250; ++z)
    for (uint32_t y = 200; y < 250; ++y)
      for (uint32_t x = 200; x < 250; ++x)
        if ((x - 225) * (x - 225) + (y - 225) * (y - 225) + (z - 225) * (z - 225) < 400) v.setVoxel(x, y, z, makeVoxel(Material::Pulp));
  v.compact();
  const BrickStats s = v.stats();
  EXPECT_GT(s.uniform_chunks, 1u);
  EXPECT_GE(s.blocks, 2u);
  const MaterialTotals t = expectGpuEqualsCpu(v);
  EXPECT_EQ(t.voxels[DS_MAT_CARIES], 64u);
}

TEST_F(MaterialCountsTest, SplitDispatchesGiveTheSameTotals) {
  const BrickVolume v = ballVolume(7);  // 4096 bricks: 64 workgroups
  CountOptions options;
  options.max_groups_per_dispatch = 3;
  TimingOut timing;
  expectGpuEqualsCpu(v, options, &timing);
  EXPECT_EQ(timing.dispatches, 22u);  // ceil(64 / 3)
  EXPECT_EQ(timing.workgroups, 64u);
}

TEST_F(MaterialCountsTest, BuiltInSelfTestVolume) {
  const BrickVolume v = selfTestVolume();
  const BrickStats s = v.stats();
  EXPECT_GT(s.dense_bricks, 0u);
  EXPECT_GT(s.uniform_bricks, 0u);
  const MaterialTotals t = expectGpuEqualsCpu(v);
  EXPECT_GT(t.voxels[DS_MAT_DENTIN], 0u);
  EXPECT_GT(t.voxels[DS_MAT_ENAMEL] * DS_FILL_FULL, t.fill_sum[DS_MAT_ENAMEL]) << "some enamel is partly filled";
}

}  // namespace dentsim::gpu::test
