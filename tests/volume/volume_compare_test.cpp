// Tests for src/volume/volume_compare.cpp: per-tissue intersection, union and IoU counted by hand and against a voxel-by-voxel tally.
#include "volume/volume_compare.h"

#include "test_volumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace dentsim {
namespace {

TEST(VolumeCompare, OneBrickCountedByHand) {
  // One 8^3 brick. Enamel in a: x = 0..3 of row (y=0, z=0), full; (0,1,0) at fill 16; (0,2,0) full.
  //                 Enamel in b: x = 2..5 of the same row, full; (0,1,0) at fill 15; (0,2,0) is dentin.
  // Inside (2 * fill > 31): a has 4 + 1 + 1 = 6, b has 4 (fill 15 is out, dentin is not enamel);
  // both hold x = 2, 3: intersection 2, union 8 (x = 0..5 and the two voxels of a), IoU 1/4.
  // Fill sums, another tissue counting 0: the row gives min 2 x 31 = 62 and max 6 x 31 = 186,
  // (0,1,0) min 15 and max 16, (0,2,0) min 0 and max 31: 77 / 233.
  BrickVolume a(3), b(3);
  for (uint32_t x = 0; x < 4; ++x) a.setVoxel(x, 0, 0, makeVoxel(Material::Enamel));
  for (uint32_t x = 2; x < 6; ++x) b.setVoxel(x, 0, 0, makeVoxel(Material::Enamel));
  a.setVoxel(0, 1, 0, makeVoxel(Material::Enamel, 16));
  b.setVoxel(0, 1, 0, makeVoxel(Material::Enamel, 15));
  a.setVoxel(0, 2, 0, makeVoxel(Material::Enamel));
  b.setVoxel(0, 2, 0, makeVoxel(Material::Dentin));

  const Result<TissueOverlap> enamel = compareTissues(a, b, Material::Enamel);
  ASSERT_TRUE(enamel.ok()) << enamel.message();
  EXPECT_EQ(enamel->a_voxels, 6u);
  EXPECT_EQ(enamel->b_voxels, 4u);
  EXPECT_EQ(enamel->intersection, 2u);
  EXPECT_EQ(enamel->union_voxels, 8u);
  EXPECT_DOUBLE_EQ(enamel->iou, 0.25);
  EXPECT_EQ(enamel->min_fill_sum, 77u);
  EXPECT_EQ(enamel->max_fill_sum, 233u);
  EXPECT_DOUBLE_EQ(enamel->soft_iou, 77.0 / 233.0);

  // Dentin is only in b, at (0,2,0): nothing shared.
  const Result<TissueOverlap> dentin = compareTissues(a, b, Material::Dentin);
  ASSERT_TRUE(dentin.ok());
  EXPECT_EQ(dentin->a_voxels, 0u);
  EXPECT_EQ(dentin->b_voxels, 1u);
  EXPECT_EQ(dentin->union_voxels, 1u);
  EXPECT_EQ(dentin->iou, 0.0);
  EXPECT_EQ(dentin->max_fill_sum, 31u);
  EXPECT_EQ(dentin->soft_iou, 0.0);

  // Pulp is in neither: two empty sets agree.
  const Result<TissueOverlap> pulp = compareTissues(a, b, Material::Pulp);
  ASSERT_TRUE(pulp.ok());
  EXPECT_EQ(pulp->union_voxels, 0u);
  EXPECT_EQ(pulp->max_fill_sum, 0u);
  EXPECT_EQ(pulp->iou, 1.0);
  EXPECT_EQ(pulp->soft_iou, 1.0);
}

TEST(VolumeCompare, TilesCountAsWholeBricks) {
  // Level 7: 16^3 bricks in 2^3 chunks. a: bricks (0,0,0) and (1,0,0) are full caries tiles, 1024
  // voxels. b: brick (0,0,0) the same tile; brick (1,0,0) dense, caries where z < 4 (256 voxels);
  // brick (15,15,15), in another chunk, a caries tile at fill 10: outside, but in the fill sums.
  // Inside: a 1024, b 768, intersection 768, union 1024, IoU 3/4.
  // Fill: min = 768 x 31; max = 1024 x 31 + 512 x 10.
  BrickVolume a(7), b(7);
  a.setBrickUniform({0, 0, 0}, makeVoxel(Material::Caries));
  a.setBrickUniform({1, 0, 0}, makeVoxel(Material::Caries));
  b.setBrickUniform({0, 0, 0}, makeVoxel(Material::Caries));
  std::vector<Voxel> half(DS_BRICK_VOXELS, 0);
  std::fill(half.begin(), half.begin() + 256, makeVoxel(Material::Caries));  // z = 0..3, as x is fastest
  b.setBrick({1, 0, 0}, half.data());
  b.setBrickUniform({15, 15, 15}, makeVoxel(Material::Caries, 10));

  const Result<TissueOverlap> o = compareTissues(a, b, Material::Caries);
  ASSERT_TRUE(o.ok()) << o.message();
  EXPECT_EQ(o->a_voxels, 1024u);
  EXPECT_EQ(o->b_voxels, 768u);
  EXPECT_EQ(o->intersection, 768u);
  EXPECT_EQ(o->union_voxels, 1024u);
  EXPECT_DOUBLE_EQ(o->iou, 0.75);
  EXPECT_EQ(o->min_fill_sum, 768u * 31u);
  EXPECT_EQ(o->max_fill_sum, 1024u * 31u + 512u * 10u);
}

TEST(VolumeCompare, DifferentLevelsAreAnError) {
  const Result<TissueOverlap> o = compareTissues(BrickVolume(5), BrickVolume(6), Material::Dentin);
  ASSERT_FALSE(o.ok());
  EXPECT_NE(o.message().find("level 5 and level 6"), std::string::npos) << o.message();
}

TEST(VolumeCompare, MatchesAVoxelByVoxelTallyAndIsSymmetric) {
  const BrickVolume a = test::randomVolume(5, 1, test::NoiseMaterials::Tissues);
  const BrickVolume b = test::randomVolume(5, 2, test::NoiseMaterials::Tissues);
  // The random volumes hold a tooth's own four tissues (test_volumes.h), no neighbour.
  for (uint32_t m = 1; m < DS_MAT_NEIGHBOUR; ++m) {
    const auto tissue = Material(m);
    uint64_t in_a = 0, in_b = 0, both = 0, either = 0, lo = 0, hi = 0;
    for (uint32_t k = 0; k < 32; ++k)
      for (uint32_t j = 0; j < 32; ++j)
        for (uint32_t i = 0; i < 32; ++i) {
          const Voxel va = a.voxel(i, j, k), vb = b.voxel(i, j, k);
          const uint32_t fa = voxelMaterial(va) == tissue ? voxelFill(va) : 0;
          const uint32_t fb = voxelMaterial(vb) == tissue ? voxelFill(vb) : 0;
          in_a += fa >= 16;
          in_b += fb >= 16;
          both += fa >= 16 && fb >= 16;
          either += fa >= 16 || fb >= 16;
          lo += std::min(fa, fb);
          hi += std::max(fa, fb);
        }
    const Result<TissueOverlap> ab = compareTissues(a, b, tissue);
    const Result<TissueOverlap> ba = compareTissues(b, a, tissue);
    ASSERT_TRUE(ab.ok() && ba.ok());
    EXPECT_EQ(ab->a_voxels, in_a) << materialName(tissue);
    EXPECT_EQ(ab->b_voxels, in_b) << materialName(tissue);
    EXPECT_EQ(ab->intersection, both) << materialName(tissue);
    EXPECT_EQ(ab->union_voxels, either) << materialName(tissue);
    EXPECT_EQ(ab->min_fill_sum, lo) << materialName(tissue);
    EXPECT_EQ(ab->max_fill_sum, hi) << materialName(tissue);
    EXPECT_GT(either, 0u);  // the seeds do give every tissue
    EXPECT_EQ(ba->a_voxels, in_b);
    EXPECT_EQ(ba->iou, ab->iou);
    EXPECT_EQ(ba->soft_iou, ab->soft_iou);
    // A volume agrees with itself.
    const Result<TissueOverlap> aa = compareTissues(a, a, tissue);
    ASSERT_TRUE(aa.ok());
    EXPECT_EQ(aa->iou, 1.0);
    EXPECT_EQ(aa->soft_iou, 1.0);
    EXPECT_EQ(aa->intersection, in_a);
  }
}

}  // namespace
}  // namespace dentsim
