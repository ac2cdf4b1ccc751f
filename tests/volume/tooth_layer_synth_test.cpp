// Tests of tooth_layer_synth: axis, CEJ, enamel, pulp and errors on a hand-built two-rooted tooth whose answers are known by construction.
#include "volume/tooth_layer_synth.h"
#include "volume/tooth_layer_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "volume_fixtures.h"

namespace dentsim {
namespace {

constexpr double kVoxelMm = 0.2;  // a 100-voxel tooth is then 20 mm long, a molar's length

// The hand-built tooth, in voxels along its own axes: `a` from the apex (0) to the cusp tip (100),
// `u` across toward one root, `w` the third axis.
//   a in [0, 45):  two roots at u = -11 and +11, radius 3 at the apex growing to 8, so that they
//                  meet the trunk's outline at a = 45: below 45 every slice is two pieces.
//   a in [45, 55]: the root trunk, radius 19 narrowing to 16: the waist (the CEJ) is at a = 55,
//                  well apart from where a molar's crown/root ratio alone would put it (a = 64).
//   a in [55, 75]: the crown widens to radius 24, its height of contour at a = 75.
//   a in [75, 100]: a dome closing at the cusp tip.
bool insideTooth(double a, double u, double w) {
  if (a < 0 || a > 100) return false;
  if (a < 45) {
    const double r = 3.0 + 5.0 * a / 45.0;
    return (u - 11) * (u - 11) + w * w <= r * r || (u + 11) * (u + 11) + w * w <= r * r;
  }
  double r = 0;
  if (a <= 55) r = 19.0 - 3.0 * (a - 45) / 10.0;
  else if (a <= 75) r = 16.0 + 8.0 * (a - 55) / 20.0;
  else r = 24.0 * std::sqrt(std::max(0.0, 1.0 - (a - 75) * (a - 75) / 625.0));
  return u * u + w * w <= r * r;
}

// A one-rooted tooth 110 voxels (22 mm) long, a premolar's proportions:
//   a in [0, 55):   one root, radius 2 at the apex growing to 9.
//   a in [55, 62]:  the neck narrowing to radius 8: the waist (the CEJ) at a = 62.
//   a in [62, 80]:  the crown widens to an ellipse 35 voxels (7 mm) across u, the mesiodistal
//                   width, and 45 (9 mm) across w, the buccolingual one, its height of contour at 80.
//   a in [80, 110]: a dome closing at the cusp tip.
bool insidePremolar(double a, double u, double w) {
  if (a < 0 || a > 110) return false;
  if (a < 55) {
    const double r = 2.0 + 7.0 * a / 55.0;
    return u * u + w * w <= r * r;
  }
  if (a <= 62) {
    const double r = 9.0 - (a - 55) / 7.0;
    return u * u + w * w <= r * r;
  }
  const double t = std::min(1.0, (a - 62) / 18.0);
  double ru = 8.0 + 9.5 * t, rw = 8.0 + 14.5 * t;
  if (a > 80) {
    const double dome = std::sqrt(std::max(0.0, 1.0 - (a - 80) * (a - 80) / 900.0));
    ru *= dome;
    rw *= dome;
  }
  return ru > 0 && rw > 0 && (u / ru) * (u / ru) + (w / rw) * (w / rw) <= 1.0;
}

struct BuiltTooth {
  BrickVolume volume{7};
  Vec3 apex, axis, across, third;  // grid voxels; unit directions
  double along(uint32_t x, uint32_t y, uint32_t z) const { return dot(Vec3{x + 0.5, y + 0.5, z + 0.5} - apex, axis); }
  double acrossOf(uint32_t x, uint32_t y, uint32_t z) const {
    return dot(Vec3{x + 0.5, y + 0.5, z + 0.5} - apex, across);
  }
};

// The tooth with its apex at `apex` [voxels] and its crown toward `axis`; the roots part along the
// grid's z cross `axis` direction. One tissue, dentin, every voxel full.
BuiltTooth buildTooth(Vec3 apex, Vec3 axis, bool (*inside)(double, double, double) = insideTooth) {
  BuiltTooth t;
  t.apex = apex;
  t.axis = normalized(axis);
  t.third = Vec3{0, 0, 1};
  t.across = normalized(cross(t.third, t.axis));
  const uint32_t n = t.volume.dim();
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const Vec3 d = Vec3{x + 0.5, y + 0.5, z + 0.5} - apex;
        if (inside(dot(d, t.axis), dot(d, t.across), dot(d, t.third)))
          t.volume.setVoxel(x, y, z, makeVoxel(Material::Dentin));
      }
  return t;
}

double degreesBetween(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(dot(normalized(a), normalized(b)), -1.0, 1.0)) * 180.0 / M_PI;
}

// The axis passes through voxel centres (x.5), so the tooth is symmetric about it voxel for voxel.
const Vec3 kApexAlongX{14.0, 64.5, 64.5};

TEST(ToothLayerSynthTest, FindsTheCrownAxisTowardTheWideEnd) {
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->crown_found);
  EXPECT_LT(degreesBetween(r->crown, {1, 0, 0}), 3.0);
  // 101 slices from apex to tip: 20 mm at 0.2 mm.
  EXPECT_NEAR(r->tooth_length_mm, 101 * kVoxelMm, 2 * kVoxelMm);
}

TEST(ToothLayerSynthTest, FindsTheCrownAxisOfAFlippedTooth) {
  BuiltTooth t = buildTooth({114.0, 64.5, 64.5}, {-1, 0, 0});
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(degreesBetween(r->crown, {-1, 0, 0}), 3.0);
}

TEST(ToothLayerSynthTest, FindsTheCrownAxisOfATiltedTooth) {
  // 20 degrees about z: the principal axis must follow the tooth, not the grid.
  const double tilt = 20.0 * M_PI / 180.0;
  const Vec3 axis{std::cos(tilt), std::sin(tilt), 0};
  BuiltTooth t = buildTooth({16.0, 40.0, 64.5}, axis);
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(degreesBetween(r->crown, axis), 3.0);
}

TEST(ToothLayerSynthTest, FindsTheWaistRootsAndType) {
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  for (const std::string& line : r->lines) std::printf("  %s\n", line.c_str());
  // The waist at a = 55 by construction; heights count from the lowest voxel's slice.
  EXPECT_NEAR(r->cej_mm / kVoxelMm, 55.0, 2.0);
  EXPECT_EQ(r->roots, 2);
  EXPECT_NEAR(r->furcation_mm / kVoxelMm, 45.0, 2.0);
  // Two roots under a crown 9.6 mm wide: a molar, guessed.
  EXPECT_EQ(r->type, ToothType::Molar);
  EXPECT_TRUE(r->type_guessed);
  // The roots stand along y: that is the mesiodistal line; which end is mesial stays unknown.
  ASSERT_TRUE(r->mesiodistal.has_value());
  EXPECT_GT(std::abs(r->mesiodistal->y), 0.99);
  EXPECT_FALSE(r->mesial.has_value());
  ASSERT_FALSE(r->lines.empty());
  EXPECT_NE(r->lines[0].find("synthesized"), std::string::npos);
  EXPECT_NE(r->lines[0].find("molar"), std::string::npos);
}

TEST(ToothLayerSynthTest, TellsAOneRootedPremolarAndItsMesiodistalLine) {
  BuiltTooth t = buildTooth({9.0, 64.5, 64.5}, {1, 0, 0}, insidePremolar);
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(degreesBetween(r->crown, {1, 0, 0}), 3.0);
  EXPECT_EQ(r->roots, 1);
  EXPECT_EQ(r->furcation_mm, 0.0);
  // One root, a crown under 9 mm wide, a tooth under 24 mm, an occlusal table and no edge.
  EXPECT_EQ(r->type, ToothType::Premolar);
  EXPECT_TRUE(r->type_guessed);
  EXPECT_NEAR(r->cej_mm / kVoxelMm, 62.0, 2.0);
  // A premolar's crown is narrower mesiodistally: the minor axis of its widest slice, here y.
  ASSERT_TRUE(r->mesiodistal.has_value());
  EXPECT_GT(std::abs(r->mesiodistal->y), 0.99);
  EXPECT_FALSE(r->mesial.has_value());
}

TEST(ToothLayerSynthTest, CapsTheCrownWithEnamelThickestAtTheTop) {
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  LayerSynthOptions opt;
  opt.type = ToothType::Molar;
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, opt);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r->type_guessed);
  const double cej = r->cej_mm / kVoxelMm;
  // Enamel only above the CEJ (within two voxels), and every tooth voxel still tissue.
  uint64_t enamel = 0;
  const uint32_t n = t.volume.dim();
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const Voxel v = t.volume.voxel(x, y, z);
        if (voxelMaterial(v) != Material::Enamel) continue;
        ++enamel;
        EXPECT_GE(t.along(x, y, z), cej - 2.0) << x << " " << y << " " << z;
      }
  EXPECT_GT(enamel, 0u);
  // Along the axis from the cusp tip (x = 113) down: enamel voxels before the first dentin one.
  int top = 0;
  for (int x = 113; x > 14 && voxelMaterial(t.volume.voxel(uint32_t(x), 64, 64)) == Material::Enamel; --x) ++top;
  // Across the crown 1 mm above the waist (a = 60, x = 74), in from its surface at +y.
  int side = 0;
  for (int y = 127; y > 64; --y) {
    const Material m = voxelMaterial(t.volume.voxel(74, uint32_t(y), 64));
    if (m == Material::Empty) continue;
    if (m != Material::Enamel) break;
    ++side;
  }
  EXPECT_GT(side, 0);
  EXPECT_GT(top, side);
  // The top is the type's full thickness (1.7 mm = 8.5 voxels) or more, under a convex dome.
  EXPECT_GE(top * kVoxelMm, r->enamel_cusp_mm - kVoxelMm);
}

TEST(ToothLayerSynthTest, PutsThePulpInsideTheDentinAndDownEachRoot) {
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_GT(r->pulp_mm3, 0.0);
  const uint32_t n = t.volume.dim();
  uint64_t root_pulp[2] = {0, 0};  // -y root, +y root, between a = 10 and 30
  for (uint32_t z = 1; z + 1 < n; ++z)
    for (uint32_t y = 1; y + 1 < n; ++y)
      for (uint32_t x = 1; x + 1 < n; ++x) {
        if (voxelMaterial(t.volume.voxel(x, y, z)) != Material::Pulp) continue;
        // Enclosed: every face neighbour is pulp or dentin, never empty or enamel.
        const uint32_t nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
        for (const auto& q : nb) {
          const Material m = voxelMaterial(t.volume.voxel(q[0], q[1], q[2]));
          EXPECT_TRUE(m == Material::Pulp || m == Material::Dentin) << x << " " << y << " " << z;
        }
        const double a = t.along(x, y, z);
        // The canals stop 1 mm (5 voxels) short of the apices.
        EXPECT_GE(a, 5.0 - 1.0);
        if (a >= 10 && a <= 30) ++root_pulp[t.acrossOf(x, y, z) > 0 ? 1 : 0];
      }
  EXPECT_GT(root_pulp[0], 0u);
  EXPECT_GT(root_pulp[1], 0u);
}

TEST(ToothLayerSynthTest, LeavesANeighbourToothAlone) {
  // A neighbour block beside the crown (the tooth reaches y = 88 at most): not this tooth's shape,
  // so neither its axis nor its layers, and every neighbour voxel stays one.
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  test::setBox(t.volume, {70, 100, 50}, {100, 120, 80}, makeVoxel(Material::Neighbour));
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(degreesBetween(r->crown, {1, 0, 0}), 3.0);
  EXPECT_EQ(r->roots, 2);
  uint64_t neighbour = 0;
  for (uint32_t z = 50; z < 80; ++z)
    for (uint32_t y = 100; y < 120; ++y)
      for (uint32_t x = 70; x < 100; ++x) neighbour += t.volume.voxel(x, y, z) == makeVoxel(Material::Neighbour);
  EXPECT_EQ(neighbour, 30u * 20u * 30u);
}

TEST(ToothLayerSynthTest, TypeNamesRoundTrip) {
  for (ToothType type : {ToothType::Molar, ToothType::Premolar, ToothType::Canine, ToothType::Incisor}) {
    const std::optional<ToothType> back = parseToothType(toothTypeName(type));
    ASSERT_TRUE(back.has_value()) << toothTypeName(type);
    EXPECT_EQ(*back, type);
    EXPECT_NE(toothTypeNames().find(toothTypeName(type)), std::string::npos);
  }
  EXPECT_STREQ(toothTypeName(ToothType::Unknown), "unknown");
  EXPECT_FALSE(parseToothType("unknown").has_value());
  EXPECT_FALSE(parseToothType("wisdom").has_value());
  EXPECT_FALSE(parseToothType("Molar").has_value());
}

TEST(ToothLayerSynthTest, RefusesAnEmptyVolume) {
  BrickVolume v(5);
  const BrickVolume before = v;
  Result<LayerSynthReport> r = synthesizeLayers(v, kVoxelMm, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no tooth voxels"), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos);
  EXPECT_TRUE(v == before);
}

TEST(ToothLayerSynthTest, RefusesATinyTooth) {
  // 6 voxels long: fewer than the 16 slices that layers need.
  BrickVolume v(5);
  test::setBox(v, {10, 10, 10}, {16, 14, 14}, makeVoxel(Material::Dentin));
  const BrickVolume before = v;
  Result<LayerSynthReport> r = synthesizeLayers(v, kVoxelMm, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("too small"), std::string::npos) << r.message();
  EXPECT_TRUE(v == before);
}

TEST(ToothLayerSynthTest, RefusesAVoxelCoarserThanTheEnamel) {
  // The built tooth at 1 mm a voxel: 100 mm long, and no enamel layer fits a voxel.
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  const BrickVolume before = t.volume;
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, 1.0, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("coarser"), std::string::npos) << r.message();
  EXPECT_TRUE(t.volume == before);
}

TEST(ToothLayerSynthTest, StopsWhenCancelledAndLeavesTheVolume) {
  struct Cancel : Interrupter {
    int asked = 0;
    bool progress(double) override { return ++asked < 2; }  // the second question cancels
  } cancel;
  BuiltTooth t = buildTooth(kApexAlongX, {1, 0, 0});
  const BrickVolume before = t.volume;
  Result<LayerSynthReport> r = synthesizeLayers(t.volume, kVoxelMm, {}, &cancel);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("cancelled"), std::string::npos) << r.message();
  EXPECT_EQ(cancel.asked, 2);
  EXPECT_TRUE(t.volume == before);
}

TEST(ToothLayerSynthTest, ComparesLayersVoxelByVoxel) {
  // Real: 2 enamel voxels, 2 dentin (one of them caries), 1 pulp. Synthesized: 1 enamel where the
  // real has enamel, the other enamel voxel as dentin, both dentin voxels dentin, the pulp as dentin.
  BrickVolume real(3), synth(3);
  real.setVoxel(1, 1, 1, makeVoxel(Material::Enamel));
  real.setVoxel(2, 1, 1, makeVoxel(Material::Enamel));
  real.setVoxel(3, 1, 1, makeVoxel(Material::Dentin));
  real.setVoxel(4, 1, 1, makeVoxel(Material::Caries));
  real.setVoxel(5, 1, 1, makeVoxel(Material::Pulp));
  synth.setVoxel(1, 1, 1, makeVoxel(Material::Enamel));
  for (uint32_t x = 2; x <= 5; ++x) synth.setVoxel(x, 1, 1, makeVoxel(Material::Dentin));
  const LayerComparison c = compareLayers(real, synth, 0.5, {0, 0, 1});
  EXPECT_DOUBLE_EQ(c.dice_enamel, 2.0 * 1 / (2 + 1));  // one shared of 2 and 1
  EXPECT_DOUBLE_EQ(c.dice_dentin, 2.0 * 2 / (2 + 4));  // caries counts as dentin: 2 shared of 2 and 4
  EXPECT_DOUBLE_EQ(c.dice_pulp, 0.0);
  // Real enamel: 2 voxels with 5 + 4 faces to empty (voxel 2's +x face meets dentin), 0.5 mm each:
  // 2 / 9 * 0.5 mm. Synthesized: 1 voxel with 5 free faces: 1 / 5 * 0.5 mm.
  EXPECT_NEAR(c.enamel_mm_real, 2.0 / 9.0 * 0.5, 1e-12);
  EXPECT_NEAR(c.enamel_mm_synth, 0.1, 1e-12);
  EXPECT_NEAR(c.enamel_error_mm, std::abs(0.1 - 1.0 / 9.0), 1e-12);
}

TEST(ToothLayerSynthTest, WholeToothShapeIsOneTissueWithFillsKept) {
  BrickVolume v(3);
  v.setVoxel(1, 1, 1, makeVoxel(Material::Enamel, 12));
  v.setVoxel(2, 1, 1, makeVoxel(Material::Pulp));
  v.setVoxel(3, 1, 1, makeVoxel(Material::Neighbour));
  const BrickVolume s = wholeToothShape(v);
  EXPECT_EQ(s.voxel(1, 1, 1), makeVoxel(Material::Dentin, 12));
  EXPECT_EQ(s.voxel(2, 1, 1), makeVoxel(Material::Dentin));
  EXPECT_EQ(s.voxel(3, 1, 1), makeVoxel(Material::Neighbour));  // another tooth is not this tooth's shape
  EXPECT_EQ(s.voxel(0, 0, 0), makeVoxel(Material::Empty));
}

}  // namespace
}  // namespace dentsim
