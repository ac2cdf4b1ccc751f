// Tests for src/volume/volume_edit.cpp: carveBall against hand counts, the ball's volume and a voxel-by-voxel reference.
#include "volume/volume_edit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

namespace dentsim {
namespace {

using Key = std::tuple<uint32_t, uint32_t, uint32_t>;  // (z, y, x): the order dirty lists are sorted in

// A voxel edge that is a power of two, with origins and centres on multiples of 1/4 voxel: every
// coordinate and squared distance below is then exact in double, so the reference and carveBall
// see the same numbers however they group their sums.
constexpr double kVoxel = 0.125;  // [mm]

VolumeFrame frameFor(int level) { return VolumeFrame::axisAligned(level, kVoxel, {-1.0, 0.5, 2.0}); }

// Every brick a tile of `v`.
BrickVolume solidBlock(int level, Voxel v) {
  BrickVolume volume(level);
  const uint32_t bd = volume.brickDim();
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) volume.setBrickUniform({x, y, z}, v);
  return volume;
}

// A mix of empty space, solid tiles and dense bricks of random tissues and fills.
BrickVolume randomTooth(int level, uint32_t seed) {
  BrickVolume volume(level);
  std::mt19937 rng(seed);
  const uint32_t bd = volume.brickDim();
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) {
        const uint32_t kind = rng() % 3;
        if (kind == 1) volume.setBrickUniform({x, y, z}, makeVoxel(Material::Dentin));
        if (kind != 2) continue;
        std::vector<Voxel> voxels(DS_BRICK_VOXELS);
        for (Voxel& v : voxels) {
          const auto m = Material(rng() % DS_TISSUE_COUNT);
          v = makeVoxel(m, 1 + rng() % DS_FILL_FULL);
        }
        volume.setBrick({x, y, z}, voxels.data());
      }
  return volume;
}

// The rule of volume_edit.h written out for one voxel, straight from its words.
Voxel carvedVoxel(Voxel v, const VolumeFrame& f, uint32_t i, uint32_t j, uint32_t k, const std::array<double, 3>& c,
                  double r) {
  const double dx = f.origin_mm[0] + (i + 0.5) * f.voxel_mm - c[0];
  const double dy = f.origin_mm[1] + (j + 0.5) * f.voxel_mm - c[1];
  const double dz = f.origin_mm[2] + (k + 0.5) * f.voxel_mm - c[2];
  const double d = std::sqrt(dx * dx + dy * dy + dz * dz) - r;  // > 0 outside [mm]
  const double inside_share = std::clamp(0.5 - d / f.voxel_mm, 0.0, 1.0);
  const auto cap = uint32_t(std::lround(31.0 * (1.0 - inside_share)));
  const uint32_t fill = std::min(voxelFill(v), cap);
  return fill == 0 ? Voxel(0) : makeVoxel(voxelMaterial(v), fill);
}

// What carveBall must report and leave behind, from the rule applied to every voxel of the grid.
struct Expected {
  BrickVolume volume;
  std::vector<Key> dirty;
  uint64_t voxels_changed = 0;
  uint64_t removed_fill = 0;  // [1/31 voxel]
};
Expected carveByReference(const BrickVolume& before, const VolumeFrame& f, const std::array<double, 3>& c, double r) {
  Expected e{before, {}, 0, 0};
  const uint32_t n = before.dim();
  std::vector<bool> brick_changed(size_t(before.brickDim()) * before.brickDim() * before.brickDim(), false);
  for (uint32_t k = 0; k < n; ++k)
    for (uint32_t j = 0; j < n; ++j)
      for (uint32_t i = 0; i < n; ++i) {
        const Voxel old = before.voxel(i, j, k);
        const Voxel now = carvedVoxel(old, f, i, j, k, c, r);
        if (now == old) continue;
        e.volume.setVoxel(i, j, k, now);
        ++e.voxels_changed;
        e.removed_fill += voxelFill(old) - voxelFill(now);
        brick_changed[layout::brickLinearIndex(i / 8, j / 8, k / 8, before.brickDim())] = true;
      }
  const uint32_t bd = before.brickDim();
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x)
        if (brick_changed[layout::brickLinearIndex(x, y, z, bd)]) e.dirty.push_back({z, y, x});
  return e;
}

std::vector<Key> keys(const std::vector<BrickCoord>& dirty) {
  std::vector<Key> out;
  for (const BrickCoord& c : dirty) out.push_back({c.z, c.y, c.x});
  return out;
}

// Centre [mm] of grid voxel (i,j,k).
std::array<double, 3> voxelCentre(const VolumeFrame& f, uint32_t i, uint32_t j, uint32_t k) {
  return {f.origin_mm[0] + (i + 0.5) * f.voxel_mm, f.origin_mm[1] + (j + 0.5) * f.voxel_mm,
          f.origin_mm[2] + (k + 0.5) * f.voxel_mm};
}

TEST(VolumeEdit, HalfVoxelBallOnACentreRemovesThatVoxelOnly) {
  // r = h/2 at a voxel centre: that voxel has d = -h/2, so c = 1 and it empties; its six face
  // neighbours have d = +h/2, so c = 0 and they keep their fill; the others are further out.
  const VolumeFrame f = frameFor(4);
  BrickVolume v = solidBlock(4, makeVoxel(Material::Enamel));
  const EditResult r = carveBall(v, f, voxelCentre(f, 3, 4, 5), 0.5 * kVoxel);
  EXPECT_EQ(r.voxels_changed, 1u);
  ASSERT_EQ(r.dirty.size(), 1u);
  EXPECT_EQ(keys(r.dirty)[0], Key(0, 0, 0));
  EXPECT_DOUBLE_EQ(r.removed_mm3, kVoxel * kVoxel * kVoxel);
  EXPECT_EQ(v.voxel(3, 4, 5), 0);
  EXPECT_EQ(v.voxel(2, 4, 5), makeVoxel(Material::Enamel));
  EXPECT_EQ(v.materialTotals().voxels[size_t(Material::Enamel)], 16u * 16u * 16u - 1u);
}

TEST(VolumeEdit, OneVoxelBallAtABrickCornerCountedByHand) {
  // r = h at the centre of voxel (8,8,8), the first voxel of brick (1,1,1). Distances in voxels:
  //   centre 0        -> d = -1,         c = 1      -> fill 0        (1 voxel,  31 units removed)
  //   6 faces 1       -> d = 0,          c = 1/2    -> round(15.5) = 16 (6 voxels, 15 units each)
  //   12 edges sqrt 2 -> d = 0.414,      c = 0.086  -> round(28.3) = 28 (12 voxels, 3 units each)
  //   8 corners sqrt 3 -> d = 0.732 > 1/2, c = 0     -> unchanged
  // 19 voxels, 31 + 90 + 36 = 157 units. Every voxel with some index 7 lies in a lower brick; no
  // changed voxel has all three at 7 (that is a corner), so brick (0,0,0) alone of the 2x2x2 stays clean.
  const VolumeFrame f = frameFor(5);
  BrickVolume v = solidBlock(5, makeVoxel(Material::Dentin));
  const EditResult r = carveBall(v, f, voxelCentre(f, 8, 8, 8), kVoxel);
  EXPECT_EQ(r.voxels_changed, 19u);
  EXPECT_NEAR(r.removed_mm3, 157.0 / 31.0 * kVoxel * kVoxel * kVoxel, 1e-15);
  const std::vector<Key> dirty{{0, 0, 1}, {0, 1, 0}, {0, 1, 1}, {1, 0, 0}, {1, 0, 1}, {1, 1, 0}, {1, 1, 1}};
  EXPECT_EQ(keys(r.dirty), dirty);
  EXPECT_EQ(v.voxel(8, 8, 8), 0);
  EXPECT_EQ(v.voxel(7, 8, 8), makeVoxel(Material::Dentin, 16));
  EXPECT_EQ(v.voxel(9, 9, 8), makeVoxel(Material::Dentin, 28));
  EXPECT_EQ(v.voxel(7, 7, 7), makeVoxel(Material::Dentin));
  EXPECT_EQ(v.materialTotals().fill_sum[size_t(Material::Dentin)], 32u * 32u * 32u * 31u - 157u);
}

TEST(VolumeEdit, RemovedVolumeIsTheBallsVolume) {
  // The rule removes the integral of c = clamp(1/2 - d/h, 0, 1) over space, sampled at voxel
  // centres and rounded to 1/31:
  //  - the ramp itself: integrating 4 pi (r+d)^2 c(d) over d in [-h/2, h/2], plus the inner ball
  //    of radius r - h/2, gives 4/3 pi r^3 + pi r h^2 / 3 exactly;
  //  - rounding: at most 1/62 voxel in each shell voxel (|d| < h/2), about 4 pi r^2 / h^2 of them,
  //    so at most 3 h / (62 r) of the ball's volume: 0.40% at r = 12 h;
  //  - sampling at centres: c is linear across most shell voxels, where the centre value is the
  //    voxel's mean exactly; the kinks at d = +-h/2 and the sphere's curvature leave errors of both
  //    signs that cancel over the surface (well under the rounding bound).
  // A rule that dropped the shell, or measured from a voxel corner, misses by about 3 h / r = 25%.
  const int level = 6;
  const VolumeFrame f = frameFor(level);
  const double r = 12 * kVoxel;
  const double ramp = 4.0 / 3.0 * std::numbers::pi * r * r * r + std::numbers::pi * r * kVoxel * kVoxel / 3.0;
  const double rounding = 3.0 * kVoxel / (62.0 * r);
  const std::vector<std::array<double, 3>> centres{{3.0, 4.5, 6.0}, {3.03125, 4.46875, 6.1875}, {2.8125, 4.75, 5.90625}};
  for (const auto& c : centres) {
    BrickVolume v = solidBlock(level, makeVoxel(Material::Dentin));
    const EditResult res = carveBall(v, f, c, r);
    EXPECT_NEAR(res.removed_mm3 / ramp, 1.0, rounding) << "centre " << c[0] << " " << c[1] << " " << c[2];
    // The report matches what left the volume.
    const double left = v.materialTotals().volumeMm3(Material::Dentin, kVoxel);
    EXPECT_NEAR(64.0 * 64.0 * 64.0 * kVoxel * kVoxel * kVoxel - left, res.removed_mm3, 1e-9);
  }
}

TEST(VolumeEdit, MatchesTheRuleVoxelForVoxel) {
  const int level = 5;
  const VolumeFrame f = frameFor(level);
  struct Cut {
    std::array<double, 3> centre;
    double radius;
  };
  // Balls across bricks, at and off voxel centres, thinner than a voxel, wider than a brick, and
  // wide enough (14.25 voxels) to hold whole bricks, tiles and dense ones, inside its inner sphere.
  const std::vector<Cut> cuts{{{0.0, 2.5, 4.0}, 0.25},   {{0.03125, 2.46875, 4.21875}, 0.40625},
                              {{-0.5, 1.0, 3.0}, 0.0625}, {{1.0, 2.0, 4.0}, 1.28125},
                              {{0.5, 2.5, 3.5}, 0.0},     {{1.0, 2.0, 4.0}, 1.78125}};
  for (size_t i = 0; i < cuts.size(); ++i) {
    BrickVolume v = randomTooth(level, uint32_t(11 + i));
    const Expected e = carveByReference(v, f, cuts[i].centre, cuts[i].radius);
    const EditResult r = carveBall(v, f, cuts[i].centre, cuts[i].radius);
    EXPECT_TRUE(v == e.volume) << "cut " << i;
    EXPECT_EQ(keys(r.dirty), e.dirty) << "cut " << i;
    EXPECT_EQ(r.voxels_changed, e.voxels_changed) << "cut " << i;
    EXPECT_NEAR(r.removed_mm3, double(e.removed_fill) / 31.0 * kVoxel * kVoxel * kVoxel, 1e-12) << "cut " << i;
    if (i == 3) {
      EXPECT_GT(e.dirty.size(), 8u);  // the wide ball does reach across bricks
    }
  }
}

TEST(VolumeEdit, CarvingEmptySpaceChangesNothing) {
  const VolumeFrame f = frameFor(6);
  BrickVolume v(6);
  const EditResult r = carveBall(v, f, {3.0, 4.5, 6.0}, 1.0);
  EXPECT_TRUE(r.dirty.empty());
  EXPECT_EQ(r.voxels_changed, 0u);
  EXPECT_EQ(r.removed_mm3, 0.0);
  EXPECT_TRUE(v == BrickVolume(6));
  EXPECT_EQ(v.stats().dense_bricks, 0u);  // no tile was opened
  EXPECT_EQ(v.stats().blocks, 0u);
}

TEST(VolumeEdit, BallPartlyOutsideTheGrid) {
  const int level = 5;
  const VolumeFrame f = frameFor(level);
  // Centred on the grid's lowest corner: one octant of the ball lies inside.
  {
    BrickVolume v = solidBlock(level, makeVoxel(Material::Enamel));
    const BrickVolume before = v;
    const double r = 10 * kVoxel;
    const Expected e = carveByReference(before, f, f.origin_mm, r);
    const EditResult res = carveBall(v, f, f.origin_mm, r);
    EXPECT_TRUE(v == e.volume);
    EXPECT_EQ(keys(res.dirty), e.dirty);
    // The centre sits on a voxel corner, so the octant's voxel centres are one eighth of a lattice
    // that is symmetric about it: RemovedVolumeIsTheBallsVolume's ramp volume and rounding bound
    // hold for the octant, an eighth each.
    const double ramp = (4.0 / 3.0 * std::numbers::pi * r * r * r + std::numbers::pi * r * kVoxel * kVoxel / 3.0) / 8.0;
    EXPECT_NEAR(res.removed_mm3 / ramp, 1.0, 3.0 * kVoxel / (62.0 * r));
  }
  // Across the highest face, off-centre.
  {
    BrickVolume v = randomTooth(level, 5);
    const std::array<double, 3> c{f.origin_mm[0] + 30.25 * kVoxel, f.origin_mm[1] + 34.0 * kVoxel, 2.5};
    const Expected e = carveByReference(v, f, c, 0.75);
    const EditResult res = carveBall(v, f, c, 0.75);
    EXPECT_TRUE(v == e.volume);
    EXPECT_EQ(keys(res.dirty), e.dirty);
    EXPECT_FALSE(res.dirty.empty());
  }
  // Wholly outside, even by a long way: nothing.
  for (const std::array<double, 3>& c : {std::array<double, 3>{-3.0, 0.5, 2.0}, {1e12, -1e12, 5.0}}) {
    BrickVolume v = solidBlock(level, makeVoxel(Material::Enamel));
    const EditResult res = carveBall(v, f, c, 1.0);
    EXPECT_TRUE(res.dirty.empty());
    EXPECT_TRUE(v == solidBlock(level, makeVoxel(Material::Enamel)));
  }
}

TEST(VolumeEdit, RepeatedCarvingIsIdempotent) {
  const VolumeFrame f = frameFor(5);
  BrickVolume v = randomTooth(5, 3);
  const std::array<double, 3> c{0.8125, 2.40625, 4.15625};
  const EditResult first = carveBall(v, f, c, 0.6);
  ASSERT_GT(first.voxels_changed, 0u);
  const BrickVolume once = v;
  const EditResult second = carveBall(v, f, c, 0.6);
  EXPECT_EQ(second.voxels_changed, 0u);
  EXPECT_TRUE(second.dirty.empty());
  EXPECT_EQ(second.removed_mm3, 0.0);
  EXPECT_TRUE(v == once);
  // A smaller ball inside the first one finds nothing left to take either.
  EXPECT_EQ(carveBall(v, f, c, 0.3).voxels_changed, 0u);
}

TEST(VolumeEdit, FillNeverIncreasesAndMaterialsStay) {
  const int level = 5;
  const VolumeFrame f = frameFor(level);
  BrickVolume v = randomTooth(level, 9);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> pos(-1.5, 5.5), rad(0.0, 0.8);
  for (int step = 0; step < 40; ++step) {
    const BrickVolume before = v;
    const std::array<double, 3> c{pos(rng) - 1.0, pos(rng) + 0.5, pos(rng) + 2.0};
    const EditResult r = carveBall(v, f, c, rad(rng));
    uint64_t changed = 0;
    for (uint32_t k = 0; k < 32; ++k)
      for (uint32_t j = 0; j < 32; ++j)
        for (uint32_t i = 0; i < 32; ++i) {
          const Voxel a = before.voxel(i, j, k), b = v.voxel(i, j, k);
          if (a == b) continue;
          ++changed;
          ASSERT_LT(voxelFill(b), voxelFill(a)) << "step " << step;
          ASSERT_TRUE(b == 0 || voxelMaterial(b) == voxelMaterial(a)) << "step " << step;
        }
    ASSERT_EQ(r.voxels_changed, changed) << "step " << step;
    ASSERT_GE(r.removed_mm3, 0.0);
  }
}

}  // namespace
}  // namespace dentsim
