// Tests for src/eval/crown_prep_margin.cpp: the finish line of cylinders cut to shoulders, chamfers, gaps, thin sides, tilts and zig-zags, against their drawn values.
#include "eval/crown_prep_margin.h"

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
// The original: a cylinder of radius 4 mm from z = 0.5 to 6.5 mm. The preparations keep it below
// their finish line, take the occlusal down to 5 mm and cut the axial wall in to radius 3 mm.
constexpr double kRadiusMm = 4.0, kBottomMm = 0.5, kTopMm = 6.5;
constexpr double kShoulderMm = 2.0;  // the finish line's height: the face between z = 39 and 40
constexpr double kPrepTopMm = 5.0;
const Vec3 kAxis{0, 0, 1};
const Vec3 kMesial{1, 0, 0};  // mesial = +x, buccal = axis x mesial = +y: phi = atan2(y, x) from the axis

// Keeps the original cylinder's voxels (by centre) where keep(r, phi, z, x) [mm, rad] says so;
// enamel at and above cej_mm, dentin below.
using Keep = std::function<bool(double r, double phi, double z, double x)>;
BrickVolume cylinder(const Keep& keep, double cej_mm = 0.0) {
  BrickVolume v(kLevel);
  const int lo = int((kCentreMm - kRadiusMm) / kVoxelMm) - 1, hi = int((kCentreMm + kRadiusMm) / kVoxelMm) + 1;
  for (int z = int(kBottomMm / kVoxelMm); z < int(kTopMm / kVoxelMm); ++z)
    for (int y = lo; y <= hi; ++y)
      for (int x = lo; x <= hi; ++x) {
        const double px = (x + 0.5) * kVoxelMm - kCentreMm, py = (y + 0.5) * kVoxelMm - kCentreMm;
        const double pz = (z + 0.5) * kVoxelMm;
        const double r = std::hypot(px, py);
        if (r > kRadiusMm || !keep(r, std::atan2(py, px), pz, px)) continue;
        v.setVoxel(uint32_t(x), uint32_t(y), uint32_t(z), makeVoxel(pz >= cej_mm ? Material::Enamel : Material::Dentin));
      }
  return v;
}

BrickVolume original(double cej_mm = 0.0) {
  return cylinder([](double, double, double, double) { return true; }, cej_mm);
}

// A shoulder whose floor is at floor(phi, x) and whose axial wall has radius wall(phi, z).
BrickVolume prepared(const std::function<double(double phi, double x)>& floor,
                     const std::function<double(double phi, double z)>& wall) {
  return cylinder([&](double r, double phi, double z, double x) {
    return z < floor(phi, x) || (z < kPrepTopMm && r <= wall(phi, z));
  });
}

BrickVolume shoulder(double wall_mm = 3.0) {
  return prepared([](double, double) { return kShoulderMm; }, [=](double, double) { return wall_mm; });
}

MarginLine found(const BrickVolume& o, const BrickVolume& p, Vec3 mesial = kMesial) {
  const Result<MarginLine> r = findMargin(o, p, kVoxelMm, kAxis, mesial);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
  return r.ok() ? *r : MarginLine{};
}

// The sector's middle angle [rad], in (-pi, pi].
double sectorMiddle(int s) {
  const double phi = (s + 0.5) * 2 * kPi / kMarginSectors;
  return phi > kPi ? phi - 2 * kPi : phi;
}

// A flat shoulder 1.0 mm wide all round (radius 4 to 3 at z = 2 mm): every sector at 2.0 mm,
// 1.0 mm wide, the line continuous and smooth.
TEST(CrownPrepMargin, OneMillimetreShoulderMeasuresOneMillimetre) {
  const MarginLine line = found(original(), shoulder());
  EXPECT_EQ(line.found_sectors, kMarginSectors);
  EXPECT_EQ(line.gaps, 0);
  EXPECT_EQ(line.gap_share, 0.0);
  EXPECT_NEAR(line.mean_width_mm, 1.0, 0.1);
  EXPECT_NEAR(line.min_width_mm, 1.0, 0.1);
  for (const MarginSector& s : line.sectors) {
    EXPECT_NEAR(s.height_mm, kShoulderMm, kVoxelMm);
    EXPECT_NEAR(s.width_mm, 1.0, 0.1);
  }
  EXPECT_LT(line.roughness_mm, kVoxelMm);
  EXPECT_NEAR(line.mean_height_mm, kShoulderMm, kVoxelMm);
  EXPECT_NEAR(line.lowest_height_mm, kShoulderMm, kVoxelMm);
  // The line's voxels are the floor's outer rim: the top layer kept, z = 39, near radius 4 mm.
  ASSERT_FALSE(line.line_voxels.empty());
  for (uint64_t key : line.line_voxels) {
    EXPECT_EQ(key >> 42, 39u);
    const double x = (double(key & 0x1FFFFF) + 0.5) * kVoxelMm - kCentreMm;
    const double y = (double((key >> 21) & 0x1FFFFF) + 0.5) * kVoxelMm - kCentreMm;
    EXPECT_GT(std::hypot(x, y), kRadiusMm - 3 * kVoxelMm);  // the staircase's rim stands in up to a diagonal
  }
  std::printf("shoulder 1.0: mean %.4f min %.4f roughness %.4f height %.4f\n", line.mean_width_mm,
              line.min_width_mm, line.roughness_mm, line.mean_height_mm);
}

// A chamfer cut by a round end of radius 1 mm whose centre runs at radius 4, 1 mm above the line:
// the profile curves from radius 4 at 2 mm to the axial wall at radius 3 at 3 mm. Full width 1.0.
TEST(CrownPrepMargin, OneMillimetreChamferMeasuresOneMillimetre) {
  const BrickVolume chamfer = prepared([](double, double) { return kShoulderMm; }, [](double, double z) {
    const double t = z - kShoulderMm - 1.0;
    return t < 0 ? kRadiusMm - std::sqrt(std::max(0.0, 1.0 - t * t)) : 3.0;
  });
  const MarginLine line = found(original(), chamfer);
  EXPECT_EQ(line.found_sectors, kMarginSectors);
  EXPECT_EQ(line.gaps, 0);
  EXPECT_NEAR(line.mean_width_mm, 1.0, 0.1);
  EXPECT_NEAR(line.min_width_mm, 1.0, 0.1);
  EXPECT_NEAR(line.mean_height_mm, kShoulderMm, 2 * kVoxelMm);
  EXPECT_LT(line.roughness_mm, kVoxelMm);
  std::printf("chamfer 1.0: mean %.4f min %.4f roughness %.4f height %.4f\n", line.mean_width_mm,
              line.min_width_mm, line.roughness_mm, line.mean_height_mm);
}

// The quarter from mesial to buccal (phi 0 to 90 deg) cut to radius 3 all the way down the root:
// there the cut meets no uncut wall, so sectors 0-17 (a quarter) have no line: one gap.
TEST(CrownPrepMargin, StepStoppingShortLeavesAGap) {
  const BrickVolume cut = cylinder([](double r, double phi, double z, double) {
    const bool quarter = phi >= 0 && phi < kPi / 2;
    return (z < kShoulderMm && !quarter) || (z < kPrepTopMm && r <= 3.0);
  });
  const MarginLine line = found(original(), cut);
  EXPECT_EQ(line.gaps, 1);
  EXPECT_NEAR(line.gap_share, 0.25, 2.0 / kMarginSectors);
  for (int s = 1; s < 17; ++s) EXPECT_FALSE(line.sectors[size_t(s)].found) << s;
  for (int s = 19; s < 71; ++s) EXPECT_TRUE(line.sectors[size_t(s)].found) << s;
  std::printf("quarter gap: found %d gaps %d share %.4f\n", line.found_sectors, line.gaps, line.gap_share);
}

// 0.4 mm wide on the mesial side (|phi| < 45 deg: wall radius 3.6), 1.0 elsewhere.
TEST(CrownPrepMargin, ThinMesialMarginIsFoundOnTheMesialSide) {
  const BrickVolume thin = prepared([](double, double) { return kShoulderMm; },
                                    [](double phi, double) { return std::abs(phi) < kPi / 4 ? 3.6 : 3.0; });
  const MarginLine line = found(original(), thin);
  EXPECT_EQ(line.found_sectors, kMarginSectors);
  EXPECT_NEAR(line.min_width_mm, 0.4, 0.1);
  int thin_sectors = 0;
  for (int s = 0; s < kMarginSectors; ++s) {
    const MarginSector& sec = line.sectors[size_t(s)];
    if (sec.width_mm >= 0.7) {
      EXPECT_NEAR(sec.width_mm, 1.0, 0.1) << s;
      continue;
    }
    ++thin_sectors;
    EXPECT_NEAR(sec.width_mm, 0.4, 0.1) << s;
    EXPECT_LT(std::abs(sectorMiddle(s)), 50 * kDeg) << s;
  }
  // 90 degrees of 5-degree sectors, give or take the one each side that straddles the step.
  EXPECT_GE(thin_sectors, 18);
  EXPECT_LE(thin_sectors, 20);
  EXPECT_NEAR(line.mean_width_mm, (18 * 0.4 + 54 * 1.0) / 72, 0.05);
  std::printf("thin mesial: min %.4f mean %.4f thin sectors %d\n", line.min_width_mm, line.mean_width_mm, thin_sectors);
}

// With mesial = +y, sectors start at +y and turn toward buccal = axis x mesial = -x: the thin +x
// side now lies at 270 deg, sectors 45-62 (lingual).
TEST(CrownPrepMargin, SectorsFollowTheMesialDirection) {
  const BrickVolume thin = prepared([](double, double) { return kShoulderMm; },
                                    [](double phi, double) { return std::abs(phi) < kPi / 4 ? 3.6 : 3.0; });
  const MarginLine line = found(original(), thin, Vec3{0, 1, 0});
  for (int s = 0; s < kMarginSectors; ++s) {
    const bool lingual_quarter = s >= 45 && s < 63;
    const bool edge = s == 44 || s == 63;  // sectors straddling the step may read either
    if (edge) continue;
    EXPECT_EQ(line.sectors[size_t(s)].width_mm < 0.7, lingual_quarter) << s;
  }
}

// A straight finish line tilted 10 deg across the tooth (z = 2 + x tan 10): its heights run from
// 2 - 4 tan 10 to 2 + 4 tan 10 mm, but a straight line bends nowhere: roughness under a voxel.
TEST(CrownPrepMargin, TiltedStraightMarginIsSmooth) {
  const double slope = std::tan(10 * kDeg);
  const BrickVolume tilted = prepared([=](double, double x) { return kShoulderMm + x * slope; },
                                      [](double, double) { return 3.0; });
  const MarginLine line = found(original(), tilted);
  EXPECT_EQ(line.found_sectors, kMarginSectors);
  EXPECT_EQ(line.gaps, 0);
  EXPECT_LT(line.roughness_mm, kVoxelMm);
  EXPECT_NEAR(line.lowest_height_mm, kShoulderMm - kRadiusMm * slope, 2 * kVoxelMm);
  EXPECT_NEAR(line.mean_width_mm, 1.0, 0.1);
  std::printf("tilted 10 deg: roughness %.4f lowest %.4f\n", line.roughness_mm, line.lowest_height_mm);
}

// A zig-zag finish line: 0 at phi = 0, 20, 40 ... deg, up 0.8 mm at 10, 30 ... (linear between).
// Each 5-degree sector's lowest point is at one of its edges, so sector heights repeat 0, 0.4, 0.4,
// 0 mm above 2 mm; each sector then stands 0.2 mm off its neighbours' mean, up or down:
// roughness = 0.2 mm.
TEST(CrownPrepMargin, ZigZagMarginHasItsHandCountedRoughness) {
  constexpr double kAmplitudeMm = 0.8;
  const BrickVolume zigzag = prepared(
      [](double phi, double) {
        const double deg = std::fmod(phi / kDeg + 360.0, 20.0);
        return kShoulderMm + kAmplitudeMm * (deg < 10 ? deg / 10 : (20 - deg) / 10);
      },
      [](double, double) { return 3.0; });
  const MarginLine line = found(original(), zigzag);
  EXPECT_EQ(line.found_sectors, kMarginSectors);
  EXPECT_NEAR(line.roughness_mm, 0.25 * kAmplitudeMm, kVoxelMm);
  EXPECT_NEAR(line.sectors[1].height_mm - line.sectors[0].height_mm, 0.5 * kAmplitudeMm, 2 * kVoxelMm);
  std::printf("zig-zag 0.8: roughness %.4f (hand 0.2)\n", line.roughness_mm);
}

// Enamel above 1.5 mm on the original: its cervical edge (the lowest enamel voxel centre, 1.525 mm)
// lies 0.475 mm under the 2 mm line.
TEST(CrownPrepMargin, LineStandsAboveTheCej) {
  constexpr double kCejMm = 1.5;
  const MarginLine line = found(original(kCejMm), shoulder());
  ASSERT_TRUE(line.mean_above_cej_mm.has_value());
  EXPECT_NEAR(*line.mean_above_cej_mm, kShoulderMm - kCejMm, kVoxelMm);
  for (const MarginSector& s : line.sectors) {
    ASSERT_TRUE(s.cej_height_mm.has_value());
    EXPECT_NEAR(*s.cej_height_mm, kCejMm, kVoxelMm);
  }
  // An all-dentin tooth has no enamel edge to stand over.
  const MarginLine dentin = found(original(100.0), shoulder());
  EXPECT_FALSE(dentin.mean_above_cej_mm.has_value());
  EXPECT_FALSE(dentin.sectors[0].cej_height_mm.has_value());
}

TEST(CrownPrepMargin, UnpreparedToothHasNoLine) {
  const BrickVolume tooth = original();
  const MarginLine line = found(tooth, tooth);
  EXPECT_EQ(line.found_sectors, 0);
  EXPECT_EQ(line.gaps, 1);
  EXPECT_EQ(line.gap_share, 1.0);
  EXPECT_TRUE(line.line_voxels.empty());
}

TEST(CrownPrepMargin, NeighbourBesideChangesNothing) {
  BrickVolume o = original(), p = shoulder();
  const MarginLine alone = found(o, p);
  // A neighbour touching the mesial side, x from 10.4 to 11.4 mm, full height.
  for (uint32_t z = 0; z < 140; ++z)
    for (uint32_t y = 100; y < 156; ++y)
      for (uint32_t x = 208; x < 228; ++x) {
        o.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
        p.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
      }
  const MarginLine beside = found(o, p);
  for (int s = 0; s < kMarginSectors; ++s) {
    EXPECT_EQ(beside.sectors[size_t(s)].found, alone.sectors[size_t(s)].found) << s;
    EXPECT_EQ(beside.sectors[size_t(s)].height_mm, alone.sectors[size_t(s)].height_mm) << s;
    EXPECT_EQ(beside.sectors[size_t(s)].width_mm, alone.sectors[size_t(s)].width_mm) << s;
  }
  EXPECT_EQ(beside.line_voxels, alone.line_voxels);
}

TEST(CrownPrepMargin, ErrorsNameTheirCause) {
  const BrickVolume tooth = original();
  const auto grids = findMargin(tooth, BrickVolume(kLevel - 1), kVoxelMm, kAxis, kMesial);
  ASSERT_FALSE(grids.ok());
  EXPECT_NE(grids.message().find("different grids"), std::string::npos) << grids.message();
  const auto none = findMargin(BrickVolume(kLevel), tooth, kVoxelMm, kAxis, kMesial);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no tooth"), std::string::npos) << none.message();
  BrickVolume neighbour_only(kLevel);
  neighbour_only.setVoxel(3, 3, 3, makeVoxel(Material::Neighbour));
  const auto only = findMargin(tooth, neighbour_only, kVoxelMm, kAxis, kMesial);
  ASSERT_FALSE(only.ok());
  EXPECT_NE(only.message().find("no tooth"), std::string::npos) << only.message();
  const auto along = findMargin(tooth, tooth, kVoxelMm, kAxis, Vec3{0, 0, -3});
  ASSERT_FALSE(along.ok());
  EXPECT_NE(along.message().find("mesial"), std::string::npos) << along.message();
  const auto zero = findMargin(tooth, tooth, kVoxelMm, Vec3{0, 0, 0}, kMesial);
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.message().find("axis"), std::string::npos) << zero.message();
}

}  // namespace
}  // namespace dentsim
