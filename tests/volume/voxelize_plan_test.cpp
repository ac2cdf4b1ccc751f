// Tests for src/volume/voxelize_plan.cpp: cost estimates against real voxelizations, the memory check, and the label import's plan hook.
#include "volume/voxelize_plan.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "io/input_budget.h"
#include "test_meshes.h"
#include "volume/label_import.h"
#include "voxelize_support.h"

namespace dentsim {
namespace {

uint64_t denseBricks(BrickVolume v) {
  v.compact();
  return v.brickWords().size() / DS_BRICK_WORDS;
}

TEST(VoxelizePlan, DenseBricksEstimateErrsHighButNotWildly) {
  // A sphere and a tooth-like pair of nested shells: the estimate from the triangles' area must be
  // at least the dense bricks the CPU voxelizer really makes, and within 3 times of it.
  const TriangleMesh outer = test::uvSphere({1, 2, 3}, 5.0, 192, 96);
  const TriangleMesh inner = test::uvSphere({1.3, 2, 2.6}, 3.0, 128, 64);
  const std::vector<MeshLayer> layers{{Material::Enamel, &outer, "outer"}, {Material::Dentin, &inner, "inner"}};
  for (int level : {6, 7, 8}) {
    SCOPED_TRACE("level " + std::to_string(level));
    const RaySetup setup = test::raySetupFor(layers, level, {}, nullptr);
    const VoxelizeCost cost = estimateMeshVoxelize(setup, false);
    auto v = voxelizeCpu(setup, {});
    ASSERT_TRUE(v.ok()) << v.message();
    const uint64_t dense = denseBricks(std::move(v).value());
    EXPECT_GE(cost.surface_bricks, dense);
    EXPECT_LE(cost.surface_bricks, 3 * dense);
    EXPECT_EQ(cost.level, level);
    EXPECT_EQ(cost.rays, uint64_t(setup.ray_x1 - setup.ray_x0) * (setup.ray_y1 - setup.ray_y0));
    // Memory holds at least the dense bricks themselves and the per-ray lists of the CPU path.
    EXPECT_GE(cost.memory_bytes, dense * DS_BRICK_VOXELS + cost.rays * 24);
  }
}

TEST(VoxelizePlan, EachLevelCostsAboutFourTimesTheLast) {
  // A surface's bricks grow with the square of the grid, so one level more is about 4 times the
  // dense bricks; the CPU path's rays grow 4 times too.
  const TriangleMesh s = test::uvSphere({0, 0, 0}, 4.0, 96, 48);
  const std::vector<MeshLayer> layers{{Material::Dentin, &s, "sphere"}};
  const VoxelizeCost l9 = estimateMeshVoxelize(test::raySetupFor(layers, 9, {}, nullptr), false);
  const VoxelizeCost l10 = estimateMeshVoxelize(test::raySetupFor(layers, 10, {}, nullptr), false);
  EXPECT_NEAR(double(l10.surface_bricks) / double(l9.surface_bricks), 4.0, 0.1);
  EXPECT_NEAR(double(l10.rays) / double(l9.rays), 4.0, 0.1);
  EXPECT_GT(l10.seconds, 3.0 * l9.seconds);
}

TEST(VoxelizePlan, DescribesTheJobInOneLine) {
  VoxelizeCost c;
  c.level = 12;
  c.surface_bricks = 1234567;
  c.memory_bytes = 2'500'000'000;
  c.seconds = 300;
  EXPECT_EQ(describeCost(c), "level 12 (4096^3 voxels): about 1 234 567 dense bricks, 2.5 GB of memory and 5 min");
  c.seconds = 0.2;
  EXPECT_NE(describeCost(c).find("under a second"), std::string::npos);
}

TEST(VoxelizePlan, RefusesBeyondFreeMemoryUnlessForced) {
  VoxelizeCost c;
  c.level = 13;
  c.surface_bricks = 10'000'000;
  c.memory_bytes = 16'000'000'000;
  c.seconds = 900;
  const Status refused = checkAffordable(c, 8'000'000'000, false, "voxelize");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("16 GB"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("memory budget of 8 GB"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("--force"), std::string::npos) << refused.message();
  EXPECT_TRUE(checkAffordable(c, 8'000'000'000, true, "voxelize").ok());
  EXPECT_TRUE(checkAffordable(c, 0, false, "voxelize").ok());  // unknown: never refused
  EXPECT_TRUE(checkAffordable(c, 20'000'000'000, false, "voxelize").ok());
}

TEST(VoxelizePlan, RefusesMeshesThatAreNotATooth) {
  // 200 copies of one sphere: every ray through it crosses 400 surfaces, where a tooth's crosses a
  // few; such a file costs memory and time with every crossing, so it needs --force.
  const TriangleMesh s = test::uvSphere({0, 0, 0}, 4.0, 24, 12);
  TriangleMesh pile;
  for (int i = 0; i < 200; ++i) test::appendMesh(pile, s);
  const std::vector<MeshLayer> one{{Material::Dentin, &s, "sphere"}}, many{{Material::Dentin, &pile, "pile"}};
  const VoxelizeCost tooth_like = estimateMeshVoxelize(test::raySetupFor(one, 7, {}, nullptr), false);
  const VoxelizeCost piled = estimateMeshVoxelize(test::raySetupFor(many, 7, {}, nullptr), false);
  // The sphere fills about pi/4 of its square footprint and is crossed twice there.
  EXPECT_NEAR(tooth_like.crossings_per_ray, 2 * 0.785, 0.1);
  EXPECT_NEAR(piled.crossings_per_ray, 200 * tooth_like.crossings_per_ray, 1.0);
  EXPECT_TRUE(checkAffordable(tooth_like, 0, false, "voxelize").ok());
  const Status refused = checkAffordable(piled, 0, false, "voxelize");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("times on average"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("--force"), std::string::npos) << refused.message();
  EXPECT_TRUE(checkAffordable(piled, 0, true, "voxelize").ok());
}

TEST(VoxelizePlan, MemoryBudgetIsHalfTheMachineOrTheFlag) {
  // By default half of MemTotal, never more than MemAvailable; --max-memory-mb (setMemoryBudget)
  // replaces the rule, and 0 brings it back.
  const MachineMemory m = machineMemory();
  ASSERT_GT(m.total_bytes, 0u);
  ASSERT_GT(m.available_bytes, 0u);
  const uint64_t budget = memoryBudgetBytes();
  EXPECT_LE(budget, m.total_bytes / 2 + 1);
  EXPECT_GT(budget, 0u);
  // MemAvailable moves between the two reads: compare with the smaller of half and a fresh read, loosely.
  EXPECT_GE(double(budget), 0.9 * double(std::min(m.total_bytes / 2, machineMemory().available_bytes)));
  EXPECT_NE(memoryBudgetOrigin().find("half of this machine's"), std::string::npos) << memoryBudgetOrigin();
  setMemoryBudget(uint64_t{300} << 20);
  EXPECT_EQ(memoryBudgetBytes(), uint64_t{300} << 20);
  EXPECT_EQ(memoryBudgetOrigin(), "set with --max-memory-mb");
  VoxelizeCost c;
  c.level = 13;
  c.memory_bytes = 4'700'000'000;
  const Status refused = checkAffordable(c, memoryBudgetBytes(), false, "voxelize");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("4.7 GB of memory"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("memory budget of 0.31 GB"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("--max-memory-mb"), std::string::npos) << refused.message();
  setMemoryBudget(0);
  EXPECT_EQ(memoryBudgetBytes() > (uint64_t{300} << 20), m.total_bytes / 2 > (uint64_t{400} << 20));
}

TEST(VoxelizePlan, LabelImportAsksBeforeItResamples) {
  // The import calls its plan hook once, with the level it settled on, before any voxel is made;
  // an error from the hook ends the import with that error.
  LabelImage im;
  im.dims = {20, 20, 20};
  im.pitch_mm = {0.1, 0.1, 0.1};
  im.scanner_from_voxel = {0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 0.1, 0};
  im.labels.assign(size_t(im.voxelCount()), 0);
  for (int k = 5; k < 15; ++k)
    for (int j = 5; j < 15; ++j)
      for (int i = 5; i < 15; ++i) im.labels[im.index(i, j, k)] = 3;
  LabelImportOptions opt;
  opt.map = parseLabelMap("3=dentin").value();
  opt.level = 7;
  int calls = 0;
  VoxelizeCost seen;
  opt.approve = [&](const VoxelizeCost& c) -> Status {
    ++calls;
    seen = c;
    return makeError("voxelize", "too large");
  };
  Result<ToothVolume> r = importLabels(im, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "voxelize: too large");
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(seen.level, 7);
  // The block's 6 faces of 10 x 10 source voxels, each 0.1 mm, in target voxels of 1.0 / 124 mm:
  // 6 * 1 mm^2 / (1/124 mm)^2 = 92 256 voxel faces -> 92 256 / 64 = 1441.5 -> 1442 bricks. The
  // faces are counted voxel face by voxel face, a staircase's own area, so there is no factor for
  // slope as there is for a mesh's triangles; a face aligned with the grid crosses 1441 bricks.
  EXPECT_EQ(seen.surface_bricks, 1442u);
}

}  // namespace
}  // namespace dentsim
