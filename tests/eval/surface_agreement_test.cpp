// Tests of measureSurfaceAgreement: box cavities in a slab whose faces, walls and deviations are counted by hand, the wall rule, a class V, the picture's marks, the JSON, frame checks.
#include "eval/surface_agreement.h"

#include <gtest/gtest.h>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::emptyTooth;
using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;
const Vec3 kOcclusal{0, 0, 1};  // the bur comes in from +z

// The slab (z 0..7) with the box x 4..9, y 4..9, z 4..7 cut out: 6 x 6 x 4 voxels, open at the top.
// Its surface: the floor's 6 x 6 = 36 faces (z = 3|4) and four walls of 6 x 4 = 24 faces each.
// The default tooth frame: mesial -x, buccal -y, so the mesial wall is the x = 3|4 one.
constexpr uint64_t kFloor = 36, kWall = 24, kSurface = kFloor + 4 * kWall;  // 132

ToothVolume idealBox() {
  ToothVolume t = enamelSlab();
  setBox(t, {4, 4, 4}, {10, 10, 8}, kEmpty);
  return t;
}

SurfaceAgreement measure(const ToothVolume& initial, const ToothVolume& student, const ToothVolume& ideal,
                         double band_mm = kDefaultBandMm, Vec3 axis = kOcclusal) {
  auto a = measureSurfaceAgreement(initial, student, ideal, axis, band_mm);
  EXPECT_TRUE(a.ok()) << a.message();
  return a.ok() ? *a : SurfaceAgreement{};
}

TEST(SurfaceAgreement, TheIdealItselfIsAllWithinAndEachWallIsItsOwnFaces) {
  const ToothVolume initial = enamelSlab(), ideal = idealBox();
  const SurfaceAgreement a = measure(initial, ideal, ideal);
  EXPECT_EQ(a.samples, kSurface);
  EXPECT_DOUBLE_EQ(a.area_mm2, double(kSurface) * 0.1 * 0.1);  // one 0.1 mm face each
  EXPECT_EQ(a.within, kSurface);
  EXPECT_DOUBLE_EQ(a.within_percent, 100.0);
  EXPECT_DOUBLE_EQ(a.beyond_percent, 0.0);
  EXPECT_DOUBLE_EQ(a.short_percent, 0.0);
  EXPECT_DOUBLE_EQ(a.mean_deviation_mm, 0.0);
  // Edge faces lie exactly between two walls; each goes to the wall it belongs to.
  EXPECT_EQ(a.wall(CavityWall::OcclusalFloor).samples, kFloor);
  for (CavityWall w : {CavityWall::Mesial, CavityWall::Distal, CavityWall::Buccal, CavityWall::Lingual})
    EXPECT_EQ(a.wall(w).samples, kWall) << a.wall(w).wall;
  EXPECT_EQ(a.wall(CavityWall::Occlusal).samples, 0u);
  EXPECT_EQ(a.wall(CavityWall::Gingival).samples, 0u);
  EXPECT_EQ(a.wall(CavityWall::Mesial).wall, "mesial");
  EXPECT_EQ(a.wall(CavityWall::OcclusalFloor).wall, "occlusal_floor");
}

TEST(SurfaceAgreement, OneVoxelWiderMesiallyPutsTheMesialWallBeyondANarrowBand) {
  // The student also cuts x = 3: every mesial face's kept voxel is gone, and the student's
  // tissue is one voxel (0.1 mm) from it (x = 2, the floor below, or the walls beside). With a
  // 0.05 mm band that is beyond; the other walls and the floor are the student's surface too.
  const ToothVolume initial = enamelSlab(), ideal = idealBox();
  ToothVolume student = initial;
  setBox(student, {3, 4, 4}, {10, 10, 8}, kEmpty);
  const SurfaceAgreement a = measure(initial, student, ideal, 0.05);
  EXPECT_EQ(a.samples, kSurface);
  EXPECT_EQ(a.beyond, kWall);
  EXPECT_EQ(a.within, kSurface - kWall);
  EXPECT_EQ(a.short_, 0u);
  const WallAgreement& mesial = a.wall(CavityWall::Mesial);
  EXPECT_EQ(mesial.samples, kWall);
  EXPECT_DOUBLE_EQ(mesial.beyond_percent, 100.0);
  EXPECT_NEAR(mesial.mean_deviation_mm, 0.1, 1e-12);
  for (CavityWall w : {CavityWall::OcclusalFloor, CavityWall::Distal, CavityWall::Buccal, CavityWall::Lingual}) {
    EXPECT_DOUBLE_EQ(a.wall(w).within_percent, 100.0) << a.wall(w).wall;
    EXPECT_DOUBLE_EQ(a.wall(w).mean_deviation_mm, 0.0) << a.wall(w).wall;
  }
  EXPECT_NEAR(a.beyond_percent, 100.0 * 24 / 132, 1e-9);
  // The picture marks the kept voxel behind each face: red behind the mesial wall, green under the floor.
  EXPECT_EQ(a.marks.at(3, 6, 6), kMarkBeyond);
  EXPECT_EQ(a.marks.at(6, 6, 3), kMarkWithin);
  EXPECT_EQ(a.marks.at(6, 6, 6), 0u);  // inside the cavity: no face of the ideal's
  // 0.1 mm is within the default 0.2 mm band.
  EXPECT_DOUBLE_EQ(measure(initial, student, ideal).within_percent, 100.0);
}

TEST(SurfaceAgreement, DeviationIsTheDistanceToTheNearestStudentSurface) {
  // Three voxels wider mesially (x 1..9). A mesial face at (y, z) lies min(3, y - 3, 10 - y, z - 3)
  // voxels from the student's kept tissue: x = 0, the walls at y = 3 and y = 10 that the student's
  // cut meets, or the floor at z = 3. Only y = 6, 7 with z = 6, 7 reach 3 voxels (0.3 mm, beyond
  // 0.2 mm): 4 of the 24 faces. The sum over the 24 faces is 40 voxels: per y, min(m, z - 3) over
  // z = 4..7 with m = 1, 2, 3, 3, 2, 1 gives 4, 7, 9, 9, 7, 4.
  const ToothVolume initial = enamelSlab(), ideal = idealBox();
  ToothVolume student = initial;
  setBox(student, {1, 4, 4}, {10, 10, 8}, kEmpty);
  const SurfaceAgreement a = measure(initial, student, ideal);
  const WallAgreement& mesial = a.wall(CavityWall::Mesial);
  EXPECT_EQ(mesial.beyond, 4u);
  EXPECT_EQ(mesial.within, 20u);
  EXPECT_NEAR(mesial.mean_deviation_mm, 40 * 0.1 / 24, 1e-12);
  EXPECT_EQ(a.beyond, 4u);
  EXPECT_EQ(a.within, kSurface - 4);
}

TEST(SurfaceAgreement, AShallowFloorIsShort) {
  // The ideal is 5 deep (z 3..7); the student stops 3 voxels higher (z 6..7). Every floor face's
  // cavity voxel (z = 3) is 3 voxels (0.3 mm) under the student's floor: short. On each wall, rows
  // z = 3, 4, 5 are 0.3, 0.2 and 0.1 mm short and rows 6, 7 are the student's wall: only row 3 is
  // beyond the band, 6 of 30 faces; the wall's mean is -(0.3 + 0.2 + 0.1) / 5 = -0.12 mm.
  const ToothVolume initial = enamelSlab();
  ToothVolume ideal = initial, student = initial;
  setBox(ideal, {4, 4, 3}, {10, 10, 8}, kEmpty);
  setBox(student, {4, 4, 6}, {10, 10, 8}, kEmpty);
  const SurfaceAgreement a = measure(initial, student, ideal);
  EXPECT_EQ(a.samples, 36u + 4 * 30);
  const WallAgreement& floor = a.wall(CavityWall::OcclusalFloor);
  EXPECT_EQ(floor.samples, 36u);
  EXPECT_DOUBLE_EQ(floor.short_percent, 100.0);
  EXPECT_NEAR(floor.mean_deviation_mm, -0.3, 1e-12);
  for (CavityWall w : {CavityWall::Mesial, CavityWall::Distal, CavityWall::Buccal, CavityWall::Lingual}) {
    const WallAgreement& wall = a.wall(w);
    EXPECT_EQ(wall.samples, 30u) << wall.wall;
    EXPECT_EQ(wall.short_, 6u) << wall.wall;
    EXPECT_EQ(wall.within, 24u) << wall.wall;
    EXPECT_NEAR(wall.mean_deviation_mm, -0.12, 1e-12) << wall.wall;
  }
  EXPECT_EQ(a.short_, 36u + 4 * 6);
  EXPECT_NEAR(a.short_percent, 100.0 * 60 / 156, 1e-9);
  EXPECT_EQ(a.beyond, 0u);
  EXPECT_EQ(a.marks.at(6, 6, 2), kMarkShort);
}

TEST(SurfaceAgreement, AClassVFloorIsTheAxialWallAndItsSidesAreNamedByTheToothFrame) {
  // Tissue y 8..15 (the buccal surface at y = 8, buccal being -y); the cavity x 4..9, y 8..11,
  // z 4..9, cut from the buccal side: insertion axis -y. The axial wall (y = 11|12) is the floor,
  // 6 x 6 faces; the x sides are mesial and distal, and the z sides, facing along the crown axis,
  // gingival (z = 3|4, facing the crown) and occlusal (z = 9|10); each side 4 x 6 faces.
  ToothVolume initial = emptyTooth();
  setBox(initial, {0, 8, 0}, {16, 16, 16}, makeVoxel(Material::Enamel));
  ToothVolume ideal = initial;
  setBox(ideal, {4, 8, 4}, {10, 12, 10}, kEmpty);
  const SurfaceAgreement a = measure(initial, ideal, ideal, kDefaultBandMm, {0, -1, 0});
  EXPECT_EQ(a.samples, 36u + 4 * 24);
  EXPECT_EQ(a.wall(CavityWall::OcclusalFloor).samples, 36u);
  for (CavityWall w : {CavityWall::Mesial, CavityWall::Distal, CavityWall::Occlusal, CavityWall::Gingival})
    EXPECT_EQ(a.wall(w).samples, 24u) << a.wall(w).wall;
  EXPECT_EQ(a.wall(CavityWall::Buccal).samples, 0u);
  EXPECT_EQ(a.wall(CavityWall::Lingual).samples, 0u);
  const nlohmann::ordered_json j = surfaceAgreementJson(a);
  ASSERT_EQ(j["walls"].size(), 7u);
  EXPECT_EQ(j["walls"]["gingival"]["samples"], 24);
  EXPECT_EQ(j["walls"]["buccal"]["samples"], 0);
}

TEST(SurfaceAgreement, TheWallRule) {
  const ToothAxes tooth;  // crown +z, mesial -x, buccal -y
  const Vec3 own{0, 0, 1};
  // Within 45 degrees of the axis: the floor.
  EXPECT_EQ(cavityWallOf({0.3, 0.2, 1}, own, kOcclusal, tooth), CavityWall::OcclusalFloor);
  // A wall is named for the side it stands on, opposite to where it faces.
  EXPECT_EQ(cavityWallOf({1, 0, 0.5}, own, kOcclusal, tooth), CavityWall::Mesial);   // faces distally (+x)
  EXPECT_EQ(cavityWallOf({-1, 0.2, 0}, own, kOcclusal, tooth), CavityWall::Distal);
  EXPECT_EQ(cavityWallOf({0.2, 1, 0}, own, kOcclusal, tooth), CavityWall::Buccal);   // faces lingually (+y)
  EXPECT_EQ(cavityWallOf({0, -1, 0}, own, kOcclusal, tooth), CavityWall::Lingual);
  // Exactly 45 degrees, or exactly between two walls: the face's own direction decides.
  EXPECT_EQ(cavityWallOf({1, 0, 1}, {0, 0, 1}, kOcclusal, tooth), CavityWall::OcclusalFloor);
  EXPECT_EQ(cavityWallOf({1, 0, 1}, {1, 0, 0}, kOcclusal, tooth), CavityWall::Mesial);
  EXPECT_EQ(cavityWallOf({1, 1, 0}, {0, 1, 0}, kOcclusal, tooth), CavityWall::Buccal);
  // A class V (bur along -y): a face turned toward the roots stands on the occlusal side.
  EXPECT_EQ(cavityWallOf({0, 0, -1}, {0, 0, -1}, {0, -1, 0}, tooth), CavityWall::Occlusal);
  EXPECT_EQ(cavityWallOf({0, -1, 0}, {0, -1, 0}, {0, -1, 0}, tooth), CavityWall::OcclusalFloor);
}

TEST(SurfaceAgreement, JsonHoldsTheFiveWallsOfAClassI) {
  const ToothVolume initial = enamelSlab(), ideal = idealBox();
  const nlohmann::ordered_json j = surfaceAgreementJson(measure(initial, ideal, ideal));
  EXPECT_EQ(j["band_mm"], 0.2);
  EXPECT_EQ(j["samples"], kSurface);
  EXPECT_EQ(j["within_percent"], 100.0);
  std::vector<std::string> keys;
  for (const auto& item : j["walls"].items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"occlusal_floor", "mesial", "distal", "buccal", "lingual"}));
  for (const char* field : {"samples", "area_mm2", "within_percent", "beyond_percent", "short_percent", "mean_deviation_mm"})
    EXPECT_TRUE(j["walls"]["mesial"].contains(field)) << field;
}

TEST(SurfaceAgreement, AnIdealThatRemovedNothingHasNoSurface) {
  const ToothVolume initial = enamelSlab();
  const SurfaceAgreement a = measure(initial, initial, initial);
  EXPECT_EQ(a.samples, 0u);
  EXPECT_DOUBLE_EQ(a.within_percent, 0.0);
}

TEST(SurfaceAgreement, VolumesOnAnotherGridAreAnError) {
  const ToothVolume initial = enamelSlab(), ideal = idealBox();
  ToothVolume other = ideal;
  other.frame.voxel_mm = 0.05;
  auto a = measureSurfaceAgreement(initial, initial, other, kOcclusal);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("ideal"), std::string::npos) << a.message();
  EXPECT_NE(a.message().find("voxel size"), std::string::npos) << a.message();
  EXPECT_FALSE(measureSurfaceAgreement(initial, initial, ideal, kOcclusal, -0.1).ok());
}

}  // namespace
}  // namespace dentsim
