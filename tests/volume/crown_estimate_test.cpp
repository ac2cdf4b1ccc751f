// Tests of the crown estimate: enamel over dentin faces +z, enamel on one side faces that side, a tooth without enamel keeps +z, the extent along the axis, and a neighbour beside the tooth changes nothing.
#include "volume/crown_estimate.h"

#include <gtest/gtest.h>

#include "volume_fixtures.h"

namespace dentsim {
namespace {

using test::setBox;

TEST(CrownEstimate, EnamelOverDentinFacesUp) {
  BrickVolume v(4);
  setBox(v, {0, 0, 0}, {16, 16, 6}, makeVoxel(Material::Dentin));
  setBox(v, {0, 0, 6}, {16, 16, 8}, makeVoxel(Material::Enamel));
  const CrownEstimate c = estimateCrown(v);
  EXPECT_TRUE(c.from_enamel);
  // The tooth's centroid is at z = 4, the enamel's at 7: straight up.
  EXPECT_NEAR(c.axis.x, 0.0, 1e-12);
  EXPECT_NEAR(c.axis.y, 0.0, 1e-12);
  EXPECT_NEAR(c.axis.z, 1.0, 1e-12);
  // The tissue's bricks span z 0..8.
  EXPECT_NEAR(c.lo, 0.0, 1e-12);
  EXPECT_NEAR(c.hi, 8.0, 1e-12);
  EXPECT_NEAR(c.middle(), 4.0, 1e-12);
}

TEST(CrownEstimate, EnamelOnOneSideFacesThatSide) {
  // A tooth lying on its side, crown toward -y (as the real micro-CT molar does).
  BrickVolume v(4);
  setBox(v, {4, 2, 4}, {12, 16, 12}, makeVoxel(Material::Dentin));
  setBox(v, {4, 0, 4}, {12, 2, 12}, makeVoxel(Material::Enamel));
  const CrownEstimate c = estimateCrown(v);
  EXPECT_TRUE(c.from_enamel);
  EXPECT_NEAR(c.axis.y, -1.0, 1e-12);
  // Along -y the tissue spans y 0..16, that is -16..0.
  EXPECT_NEAR(c.lo, -16.0, 1e-12);
  EXPECT_NEAR(c.hi, 0.0, 1e-12);
}

TEST(CrownEstimate, WithoutEnamelTheCrownIsAssumedUp) {
  BrickVolume v(4);
  setBox(v, {0, 0, 0}, {16, 16, 8}, makeVoxel(Material::Dentin));
  const CrownEstimate c = estimateCrown(v);
  EXPECT_FALSE(c.from_enamel);
  EXPECT_EQ(c.axis, (Vec3{0, 0, 1}));
  // Enamel spread evenly around the tooth is no direction either.
  setBox(v, {0, 0, 0}, {16, 16, 1}, makeVoxel(Material::Enamel));
  setBox(v, {0, 0, 7}, {16, 16, 8}, makeVoxel(Material::Enamel));
  EXPECT_FALSE(estimateCrown(v).from_enamel);
}

TEST(CrownEstimate, ANeighbourBesideTheToothChangesNothing) {
  // The tooth: dentin z 0..5 under enamel z 6..7, x 0..7, in a 32^3 grid.
  BrickVolume alone(5);
  setBox(alone, {0, 0, 0}, {8, 16, 6}, makeVoxel(Material::Dentin));
  setBox(alone, {0, 0, 6}, {8, 16, 8}, makeVoxel(Material::Enamel));
  // Its neighbour: a taller block x 16..31, z 0..23 in bricks of its own, which would pull the
  // tooth's centroid 10 voxels along x and up, and stretch the extent to z 24.
  BrickVolume beside = alone;
  setBox(beside, {16, 0, 0}, {32, 16, 24}, makeVoxel(Material::Neighbour));
  const CrownEstimate a = estimateCrown(alone), b = estimateCrown(beside);
  EXPECT_TRUE(b.from_enamel);
  EXPECT_EQ(b.axis.x, a.axis.x);
  EXPECT_EQ(b.axis.y, a.axis.y);
  EXPECT_EQ(b.axis.z, a.axis.z);
  EXPECT_NEAR(b.axis.z, 1.0, 1e-12);
  EXPECT_EQ(b.lo, a.lo);
  EXPECT_EQ(b.hi, a.hi);
  EXPECT_NEAR(b.hi, 8.0, 1e-12);  // the tooth's brick, not the neighbour's z 24
}

}  // namespace
}  // namespace dentsim
