// Tests for src/eval/crown_prep_undercut.cpp: the shadow of an overhang of known area, a converging frustum's none, neighbours ignored, errors.
#include "eval/crown_prep_undercut.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "eval/crown_prep_reduction.h"
#include "volume/brick_volume.h"

namespace dentsim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kLevel = 8;          // 256 voxels a side
constexpr double kVoxelMm = 0.05;  // 12.8 mm grid
constexpr double kCentreMm = 6.4;  // the tooth's axis, x = y = 6.4 mm (a voxel face)
constexpr double kRootMm = 4.0;    // the root's radius below the margin [mm]
constexpr double kMarginMm = 2.0;  // the finish line: the face between z = 39 and 40
constexpr double kTopMm = 5.0;
const Vec3 kAxis{0, 0, 1};
const Vec3 kMesial{1, 0, 0};  // mesial = +x, buccal = +y

// A root cylinder of radius 4 mm from z = 0.5 mm up to the margin, and above it, to 5 mm, the
// voxels (by centre) whose radius is within wall(phi, z) [mm, rad].
BrickVolume tooth(const std::function<double(double phi, double z)>& wall) {
  BrickVolume v(kLevel);
  const int lo = int((kCentreMm - kRootMm) / kVoxelMm) - 1, hi = int((kCentreMm + kRootMm) / kVoxelMm) + 1;
  for (int z = int(0.5 / kVoxelMm); z < int(kTopMm / kVoxelMm); ++z)
    for (int y = lo; y <= hi; ++y)
      for (int x = lo; x <= hi; ++x) {
        const double px = (x + 0.5) * kVoxelMm - kCentreMm, py = (y + 0.5) * kVoxelMm - kCentreMm;
        const double pz = (z + 0.5) * kVoxelMm;
        const double r = std::hypot(px, py);
        if (r > (pz < kMarginMm ? kRootMm : wall(std::atan2(py, px), pz))) continue;
        v.setVoxel(uint32_t(x), uint32_t(y), uint32_t(z), makeVoxel(Material::Dentin));
      }
  return v;
}

// Radius 3 mm, but 2.5 mm from the margin up to 4 mm within 45 deg of mesial: the radius-3 rim
// above 4 mm hangs over a quarter ring whose area is pi (3^2 - 2.5^2) / 4 = 2.16 mm^2.
BrickVolume overhang() {
  return tooth([](double phi, double z) { return z < 4.0 && std::abs(phi) < kPi / 4 ? 2.5 : 3.0; });
}
const double kOverhangMm2 = kPi * (3.0 * 3.0 - 2.5 * 2.5) / 4;

UndercutMap measured(const BrickVolume& v, Vec3 axis = kAxis) {
  const Result<UndercutMap> r = measureUndercut(v, kVoxelMm, axis, kMesial, kMarginMm);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
  return r.ok() ? *r : UndercutMap{};
}

TEST(CrownPrepUndercut, StepUndercutOfKnownAreaIsFoundOnItsWall) {
  const UndercutMap map = measured(overhang());
  EXPECT_NEAR(map.area_mm2, kOverhangMm2, 0.1 * kOverhangMm2);
  // All of it faces mesial (within 45 deg of +x); a column on the 45-degree line may go either way.
  EXPECT_NEAR(map.wall_area_mm2[size_t(AxialWall::Mesial)], map.area_mm2, 4 * kVoxelMm * kVoxelMm);
  EXPECT_EQ(map.wall_area_mm2[size_t(AxialWall::Distal)], 0.0);
  // The hidden surface is the shoulder's floor under the overhang: its top layer, z = 39, one voxel per column.
  EXPECT_EQ(map.voxels.size(), size_t(std::lround(map.area_mm2 / (kVoxelMm * kVoxelMm))));
  for (uint64_t key : map.voxels) EXPECT_EQ(key >> 42, 39u);
  std::printf("overhang: area %.4f mm2 (hand %.4f), mesial %.4f, buccal %.4f, lingual %.4f\n", map.area_mm2,
              kOverhangMm2, map.wall_area_mm2[0], map.wall_area_mm2[2], map.wall_area_mm2[3]);
}

// Cast along an axis tilted 3 deg toward mesial: the mesial overhang's shadow is the same quarter
// ring moved 2 tan 3 = 0.1 mm (still within 10 %: the staircase test must not eat a real undercut).
// Seen along that path the upright radius-3 wall now leans out 3 deg on the distal side, over its
// 3 mm height: a crescent 2 R 3 tan 3 = 0.94 mm^2 by hand, but at most 3 tan 3 = 0.157 mm wide, less
// the voxel of depth (0.05 mm) the staircase test gives up along it: 0.107 mm, narrower than the
// square of 3 columns (0.15 mm) that the narrowest counted overhang, 0.1 mm, needs at 0.05 mm voxels.
// A crown seats over it within its cement space; it does not count.
TEST(CrownPrepUndercut, StepUndercutIsFoundAlongATiltedAxis) {
  const UndercutMap map = measured(overhang(), Vec3{std::sin(3 * kDeg), 0, std::cos(3 * kDeg)});
  const double mesial = map.wall_area_mm2[size_t(AxialWall::Mesial)];
  EXPECT_NEAR(mesial, kOverhangMm2, 0.1 * kOverhangMm2);
  const double crescent = 2 * 3.0 * 3.0 * std::tan(3 * kDeg);
  EXPECT_LT(map.area_mm2 - mesial, 4 * kVoxelMm * kVoxelMm);
  std::printf("overhang, axis tilted 3 deg: mesial %.4f mm2 (hand %.4f), elsewhere %.4f (a crescent of %.4f, too thin to count)\n",
              mesial, kOverhangMm2, map.area_mm2 - mesial, crescent);
}

// Walls converging upward 6 deg: every column enters once and goes down through: no shadow.
TEST(CrownPrepUndercut, ConvergingFrustumHasNone) {
  const BrickVolume frustum = tooth([](double, double z) { return 3.0 - (z - kMarginMm) * std::tan(6 * kDeg); });
  const UndercutMap map = measured(frustum);
  EXPECT_EQ(map.area_mm2, 0.0);
  EXPECT_TRUE(map.voxels.empty());
  // Cast along an axis tilted 3 deg (less than the walls' 6): the tilted columns cross the voxel
  // staircase, but a gap under one voxel is no gap, so it still reads none.
  const UndercutMap tilted = measured(frustum, Vec3{std::sin(3 * kDeg), 0, std::cos(3 * kDeg)});
  EXPECT_EQ(tilted.area_mm2, 0.0);
  std::printf("frustum: area %.4f, tilted 3 deg %.4f mm2\n", map.area_mm2, tilted.area_mm2);
}

// Tilted past the walls' 6 deg, one wall leans out over its own foot: a shadow appears, on the
// side the axis tilts away from.
TEST(CrownPrepUndercut, AxisTiltedPastTheTaperMakesAShadow) {
  const BrickVolume frustum = tooth([](double, double z) { return 3.0 - (z - kMarginMm) * std::tan(6 * kDeg); });
  const UndercutMap tilted = measured(frustum, Vec3{std::sin(12 * kDeg), 0, std::cos(12 * kDeg)});
  EXPECT_GT(tilted.area_mm2, 0.0);
  EXPECT_GT(tilted.wall_area_mm2[size_t(AxialWall::Distal)], 0.5 * tilted.area_mm2);
  std::printf("frustum tilted 12 deg: area %.4f distal %.4f mm2\n", tilted.area_mm2,
              tilted.wall_area_mm2[size_t(AxialWall::Distal)]);
}

TEST(CrownPrepUndercut, NeighbourOverheadChangesNothing) {
  BrickVolume v = overhang();
  const UndercutMap alone = measured(v);
  // A neighbour slab hanging over the whole tooth, z from 5.5 to 6 mm.
  for (uint32_t z = 110; z < 120; ++z)
    for (uint32_t y = 40; y < 216; ++y)
      for (uint32_t x = 40; x < 216; ++x) v.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
  const UndercutMap beside = measured(v);
  EXPECT_EQ(beside.area_mm2, alone.area_mm2);
  EXPECT_EQ(beside.wall_area_mm2, alone.wall_area_mm2);
  EXPECT_EQ(beside.voxels, alone.voxels);
}

// Below the margin nothing counts: with the margin at 4.5 mm the overhang is root.
TEST(CrownPrepUndercut, NothingCountsUnderTheMargin) {
  const Result<UndercutMap> r = measureUndercut(overhang(), kVoxelMm, kAxis, kMesial, 4.5);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->area_mm2, 0.0);
}

// An overhang counts where a square of 3 columns of 0.05 mm (0.1 mm, the narrowest that counts, and
// one column for the lattice) holds it: a groove two voxels deep under the wall (radius 3 mm) along
// 10 columns is a ridge the laps leave, not an undercut; three voxels deep, 10 x 3 columns of
// 0.05^2 mm^2.
TEST(CrownPrepUndercut, AShadowNarrowerThanTheCementSpaceDoesNotCount) {
  auto groove = [](uint32_t depth) {
    BrickVolume v = tooth([](double, double) { return 3.0; });
    // The wall's outermost voxel on +x is x = 187 (centre 2.975 mm) on every row y 123-132. Cut it
    // and `depth` - 1 voxels inside it from z 60 to 69; the wall at z 70 and above hangs over the groove.
    for (uint32_t y = 123; y < 133; ++y)
      for (uint32_t z = 60; z < 70; ++z)
        for (uint32_t d = 0; d < depth; ++d) v.setVoxel(187 - d, y, z, makeVoxel(Material::Empty));
    return v;
  };
  for (uint32_t thin : {1u, 2u}) {
    const UndercutMap ridge = measured(groove(thin));
    EXPECT_DOUBLE_EQ(ridge.area_mm2, 0.0) << thin;
    EXPECT_TRUE(ridge.voxels.empty()) << thin;
  }
  const UndercutMap three = measured(groove(3));
  EXPECT_NEAR(three.area_mm2, 30 * kVoxelMm * kVoxelMm, 1e-12);
  EXPECT_NEAR(three.wall_area_mm2[size_t(AxialWall::Mesial)], three.area_mm2, 1e-12);
}

// A ledge 0.3 mm out from the radius-3 wall within 45 degrees of mesial, `thick` mm along the axis
// from z = 3 mm: two voxels (0.1 mm) thick, it hides the quarter ring under it, pi (3.3^2 - 3^2) / 4
// = 1.484 mm^2; one voxel thick, it is a flake of the kind the cutter leaves at half fill over the
// voxel it cut under it, and hides nothing.
TEST(CrownPrepUndercut, AFlakeThinnerThanTheCementSpaceHidesNothing) {
  auto ledge = [](double thick) {
    return tooth([thick](double phi, double z) { return z >= 3.0 && z < 3.0 + thick && std::abs(phi) < kPi / 4 ? 3.3 : 3.0; });
  };
  const UndercutMap flake = measured(ledge(kVoxelMm));
  EXPECT_DOUBLE_EQ(flake.area_mm2, 0.0);
  EXPECT_TRUE(flake.voxels.empty());
  const UndercutMap step = measured(ledge(2 * kVoxelMm));
  const double ring = kPi * (3.3 * 3.3 - 3.0 * 3.0) / 4;
  EXPECT_NEAR(step.area_mm2, ring, 0.1 * ring);
  EXPECT_NEAR(step.wall_area_mm2[size_t(AxialWall::Mesial)], step.area_mm2, 4 * kVoxelMm * kVoxelMm);  // the 45-degree edges
}

TEST(CrownPrepUndercut, ErrorsNameTheirCause) {
  const auto none = measureUndercut(BrickVolume(kLevel), kVoxelMm, kAxis, kMesial, kMarginMm);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no tooth"), std::string::npos) << none.message();
  BrickVolume neighbour_only(kLevel);
  neighbour_only.setVoxel(3, 3, 3, makeVoxel(Material::Neighbour));
  const auto only = measureUndercut(neighbour_only, kVoxelMm, kAxis, kMesial, kMarginMm);
  ASSERT_FALSE(only.ok());
  EXPECT_NE(only.message().find("no tooth"), std::string::npos) << only.message();
  const BrickVolume v = overhang();
  const auto along = measureUndercut(v, kVoxelMm, kAxis, Vec3{0, 0, 1}, kMarginMm);
  ASSERT_FALSE(along.ok());
  EXPECT_NE(along.message().find("mesial"), std::string::npos) << along.message();
  const auto voxel = measureUndercut(v, 0.0, kAxis, kMesial, kMarginMm);
  ASSERT_FALSE(voxel.ok());
  EXPECT_NE(voxel.message().find("voxel"), std::string::npos) << voxel.message();
}

}  // namespace
}  // namespace dentsim
