// Tests for src/eval/crown_prep_taper.cpp: the TOC, wall angles, height and widths of voxelized frustums and a box, against their analytic values.
#include "eval/crown_prep_taper.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "volume/brick_volume.h"

namespace dentsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kLevel = 7;          // 128 voxels a side
constexpr double kVoxelMm = 0.05;  // 6.4 mm grid
constexpr double kCentreMm = 3.2;  // the shapes' axis, x = y = 3.2 mm (a voxel face)
constexpr double kMarginMm = 1.0;  // every shape's base, the finish line

// Sets every voxel whose centre is inside a frustum standing on the vertical line x = y = 3.2 mm
// from z = 1 to 6 mm: at height t above its base, a disc of radius 2.5 - t * shrink, its centre
// moved t * shift along +x. Voxel centres sit at (i + 0.5) * 0.05, so the base layer is at 1.025 mm and the top at
// 5.975: height 5 mm to the top faces; the base disc's extent on x is +-2.475 between centres, so
// 5 mm between faces.
void addFrustum(BrickVolume& v, double shrink_per_mm, double shift_per_mm, Material m = Material::Dentin,
                double foot_radius_mm = 0) {
  const int n = int(v.dim());
  for (int z = 0; z < n; ++z) {
    const double pz = (z + 0.5) * kVoxelMm;
    if (pz < 1.0 || pz > 6.0) continue;
    const double t = pz - 1.0;
    // A rounded foot: a quarter circle of radius f tangent to the wall at height f and to the base
    // plane f out from the wall, as a chamfer bur's ball end leaves it.
    const double f = foot_radius_mm;
    const double foot = t < f ? f - std::sqrt(f * f - (f - t) * (f - t)) : 0.0;
    const double r = 2.5 - t * shrink_per_mm + foot, cx = kCentreMm + t * shift_per_mm;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double dx = (x + 0.5) * kVoxelMm - cx, dy = (y + 0.5) * kVoxelMm - kCentreMm;
        if (dx * dx + dy * dy <= r * r) v.setVoxel(x, y, z, makeVoxel(m));
      }
  }
}

// Sets the voxel box [lo, hi) in voxel indices.
void addBox(BrickVolume& v, int x0, int y0, int z0, int x1, int y1, int z1, Material m) {
  for (int z = z0; z < z1; ++z)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) v.setVoxel(x, y, z, makeVoxel(m));
}

CrownPrepShape measured(const BrickVolume& v, Vec3 axis = {0, 0, 1}, Vec3 mesial = {1, 0, 0}) {
  Result<CrownPrepShape> r = measurePrepShape(v, kVoxelMm, axis, mesial, kMarginMm);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
  return r.ok() ? *r : CrownPrepShape{};
}

// A 2 x 3 x 4 mm box (40 x 60 x 80 voxels) from z = 1 mm: walls parallel to the axis, so every
// plane's TOC is exactly 0; the widths and height are the box's own edges between voxel faces.
TEST(CrownPrepTaper, BoxHasNoTaperAndItsOwnEdges) {
  BrickVolume v(kLevel);
  addBox(v, 44, 34, 20, 84, 94, 100, Material::Enamel);
  const CrownPrepShape s = measured(v);
  for (const TaperPlane& p : s.planes) {
    EXPECT_NEAR(p.toc_deg, 0.0, 1e-9) << p.name;
    // The band [1, 3] mm holds the 40 layers of centres 1.025 .. 2.975.
    EXPECT_EQ(p.points[0], 40) << p.name;
    EXPECT_EQ(p.points[1], 40) << p.name;
  }
  EXPECT_STREQ(s.planes[0].name, "mesiodistal");
  EXPECT_STREQ(s.planes[1].name, "buccolingual");
  EXPECT_NEAR(s.height_mm, 4.0, 1e-9);
  EXPECT_NEAR(s.width_md_mm, 2.0, 1e-9);
  EXPECT_NEAR(s.width_bl_mm, 3.0, 1e-9);
  EXPECT_NEAR(s.height_width_ratio, 4.0 / 3.0, 1e-9);  // over the larger width, 3 mm
}

// A round frustum of 6 deg half-angle: each wall 6 deg, TOC 12 deg in every plane; height 5 mm,
// widths 5 mm at the base, ratio 5 / 5 = 1.
TEST(CrownPrepTaper, SixDegreeFrustumConvergesTwelveInEveryPlane) {
  BrickVolume v(kLevel);
  addFrustum(v, std::tan(6 * kDeg), 0);
  const CrownPrepShape s = measured(v);
  for (const TaperPlane& p : s.planes) {
    EXPECT_NEAR(p.toc_deg, 12.0, 1.5) << p.name;
    EXPECT_NEAR(p.wall_deg[0], 6.0, 1.0) << p.name;
    EXPECT_NEAR(p.wall_deg[1], 6.0, 1.0) << p.name;
    EXPECT_GE(p.points[0], kMinWallPoints) << p.name;
  }
  EXPECT_NEAR(s.height_mm, 5.0, kVoxelMm);
  EXPECT_NEAR(s.width_md_mm, 5.0, 2 * kVoxelMm);
  EXPECT_NEAR(s.width_bl_mm, 5.0, 2 * kVoxelMm);
  EXPECT_DOUBLE_EQ(s.height_width_ratio, s.height_mm / std::max(s.width_md_mm, s.width_bl_mm));
}

// The same 6 deg frustum standing on a chamfer's rounded foot of radius 0.5 mm (the base juts out
// 0.5 mm and curves up into the wall by 0.5 mm): the axial wall still reads 6 deg a side, TOC 12 in
// every plane. Fitted from the margin, the foot's outward run would pull each wall's line steeper
// (10 bins of the 40 lie on it); the fit leaves out at least the foot's lower part, and nothing of
// the plain frustum, whose voxel steps stay within half a voxel outside its line.
TEST(CrownPrepTaper, RoundedChamferFootIsNotReadAsTaper) {
  BrickVolume v(kLevel);
  addFrustum(v, std::tan(6 * kDeg), 0, Material::Dentin, 0.5);
  const CrownPrepShape s = measured(v);
  for (const TaperPlane& p : s.planes) {
    EXPECT_NEAR(p.toc_deg, 12.0, 1.0) << p.name << " skipped " << p.foot_skipped[0] << " " << p.foot_skipped[1];
    EXPECT_NEAR(p.wall_deg[0], 6.0, 1.0) << p.name;
    EXPECT_NEAR(p.wall_deg[1], 6.0, 1.0) << p.name;
    EXPECT_GE(p.foot_skipped[0], 3) << p.name;
    EXPECT_LE(p.foot_skipped[0], 20) << p.name;  // never below the upper half
  }
  // The margin's width is the foot's outer edge at the base layer's centres, 0.025 mm up:
  // 5 + 2 * (0.5 - sqrt(0.5^2 - 0.475^2)) = 5.69 mm.
  EXPECT_NEAR(s.width_md_mm, 5.0 + 2 * (0.5 - std::sqrt(0.25 - 0.475 * 0.475)), 2 * kVoxelMm);
  BrickVolume plain(kLevel);
  addFrustum(plain, std::tan(6 * kDeg), 0);
  for (const TaperPlane& p : measured(plain).planes) {
    EXPECT_NEAR(p.toc_deg, 12.0, 1.0) << p.name;
    EXPECT_EQ(p.foot_skipped[0] + p.foot_skipped[1], 0) << p.name;  // its staircase never juts out half a voxel
  }
}

// 15 deg half-angle: TOC 30 deg, past Goodacre's 20.
TEST(CrownPrepTaper, FifteenDegreeFrustumConvergesThirty) {
  BrickVolume v(kLevel);
  addFrustum(v, std::tan(15 * kDeg), 0);
  const CrownPrepShape s = measured(v);
  for (const TaperPlane& p : s.planes) EXPECT_NEAR(p.toc_deg, 30.0, 1.5) << p.name;
  EXPECT_NEAR(s.height_mm, 5.0, kVoxelMm);
}

// An oblique frustum: discs shrinking by tan(10)/2 per mm while their centre moves -tan(10)/2, so
// the -x (distal) face stays at x = 0.7 mm, vertical, and the +x (mesial) face leans in 10 deg. In
// the mesiodistal plane: walls 10 and 0, TOC 10. Across it the disc's radius shrinks by tan(10)/2
// on each side: walls atan(tan(10)/2) = 5.04 deg, TOC 10.07.
TEST(CrownPrepTaper, OneSidedTiltShowsInItsPlane) {
  BrickVolume v(kLevel);
  const double k = std::tan(10 * kDeg) / 2;
  addFrustum(v, k, -k);
  const CrownPrepShape s = measured(v);
  const TaperPlane& md = s.planes[0];
  EXPECT_NEAR(md.toc_deg, 10.0, 1.5);
  EXPECT_NEAR(md.wall_deg[0], 10.0, 1.0);  // mesial, +x
  EXPECT_NEAR(md.wall_deg[1], 0.0, 1.0);   // distal, vertical
  const TaperPlane& bl = s.planes[1];
  EXPECT_NEAR(bl.wall_deg[0], std::atan(k) / kDeg, 1.0);
  EXPECT_NEAR(bl.wall_deg[1], std::atan(k) / kDeg, 1.0);
  EXPECT_NEAR(s.width_md_mm, 5.0, 2 * kVoxelMm);
  // With mesial given as -x the walls swap sides: the leaning one is now [1].
  const CrownPrepShape flipped = measured(v, {0, 0, 1}, {-1, 0, 0});
  EXPECT_DOUBLE_EQ(flipped.planes[0].wall_deg[1], md.wall_deg[0]);
  EXPECT_DOUBLE_EQ(flipped.planes[0].wall_deg[0], md.wall_deg[1]);
}

// A neighbour block 0.1 mm beside the mesial wall, inside the mesiodistal slab and the band,
// changes no figure: only the treated tooth's tissues count.
TEST(CrownPrepTaper, NeighbourBesideChangesNothing) {
  BrickVolume alone(kLevel);
  addFrustum(alone, std::tan(6 * kDeg), 0);
  BrickVolume beside = alone;
  addBox(beside, 116, 50, 20, 126, 78, 100, Material::Neighbour);  // x 5.8 .. 6.3 mm; the tooth ends at 5.7
  const CrownPrepShape a = measured(alone), b = measured(beside);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(a.planes[k].toc_deg, b.planes[k].toc_deg);
    EXPECT_EQ(a.planes[k].points[0], b.planes[k].points[0]);
  }
  EXPECT_EQ(a.height_mm, b.height_mm);
  EXPECT_EQ(a.width_md_mm, b.width_md_mm);
  EXPECT_EQ(a.width_bl_mm, b.width_bl_mm);
  // The same block as the tooth's own dentin counts in the mesial profile and widens it to 5.6 mm.
  BrickVolume joined = alone;
  addBox(joined, 116, 50, 20, 126, 78, 100, Material::Dentin);
  EXPECT_NEAR(measured(joined).width_md_mm, 6.3 - 0.7, 1e-9);
}

// The axis need not be +z nor of unit length, nor mesial across it: the 2 x 3 x 4 box read along +x
// from its face at x = 2.2 mm, mesial (1, 0, 1) whose part across the axis is +z.
TEST(CrownPrepTaper, AnyGridAxisAndLength) {
  BrickVolume v(kLevel);
  addBox(v, 44, 34, 20, 84, 94, 100, Material::Dentin);
  // Along +x (length 3), mesial +z: height 2 mm (x 2.2 .. 4.2), widths 4 mm (z) and 3 mm (y).
  Result<CrownPrepShape> r = measurePrepShape(v, kVoxelMm, {3, 0, 0}, {1, 0, 1}, 2.2);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_NEAR(r->height_mm, 2.0, 1e-9);
  EXPECT_NEAR(r->width_md_mm, 4.0, 1e-9);
  EXPECT_NEAR(r->width_bl_mm, 3.0, 1e-9);
  EXPECT_NEAR(r->height_width_ratio, 0.5, 1e-9);
  for (const TaperPlane& p : r->planes) EXPECT_NEAR(p.toc_deg, 0.0, 1e-9) << p.name;
}

TEST(CrownPrepTaper, ErrorsSayWhy) {
  BrickVolume empty(kLevel);
  Result<CrownPrepShape> r = measurePrepShape(empty, kVoxelMm, {0, 0, 1}, {1, 0, 0}, kMarginMm);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no tooth voxels"), std::string::npos) << r.message();

  // A neighbour alone is no tooth.
  BrickVolume neighbour(kLevel);
  addBox(neighbour, 10, 10, 10, 30, 30, 30, Material::Neighbour);
  r = measurePrepShape(neighbour, kVoxelMm, {0, 0, 1}, {1, 0, 0}, kMarginMm);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no tooth voxels"), std::string::npos) << r.message();

  // The box spans z = 1 .. 5 mm: a margin at 0.5 or 5.5 is outside it.
  BrickVolume box(kLevel);
  addBox(box, 44, 34, 20, 84, 94, 100, Material::Enamel);
  for (double margin : {0.5, 5.5}) {
    r = measurePrepShape(box, kVoxelMm, {0, 0, 1}, {1, 0, 0}, margin);
    ASSERT_FALSE(r.ok()) << margin;
    EXPECT_NE(r.message().find("outside the tooth"), std::string::npos) << r.message();
  }

  // Mesial along the axis leaves no plane to name.
  r = measurePrepShape(box, kVoxelMm, {0, 0, 1}, {0, 0, -2}, kMarginMm);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("mesial"), std::string::npos) << r.message();

  // A slab 4 voxels tall (z 1.0 .. 1.2 mm) gives each wall 4 heights, one fewer than a line needs.
  BrickVolume flat(kLevel);
  addBox(flat, 44, 34, 20, 84, 94, 24, Material::Dentin);
  r = measurePrepShape(flat, kVoxelMm, {0, 0, 1}, {1, 0, 0}, kMarginMm);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("4 heights on a wall"), std::string::npos) << r.message();
  // One layer more is enough.
  addBox(flat, 44, 34, 24, 84, 94, 25, Material::Dentin);
  EXPECT_TRUE(measurePrepShape(flat, kVoxelMm, {0, 0, 1}, {1, 0, 0}, kMarginMm).ok());
}

}  // namespace
}  // namespace dentsim
