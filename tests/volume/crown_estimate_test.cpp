// Tests of the crown estimate: enamel over dentin faces +z, enamel on one side faces that side, a tooth without enamel keeps +z, and the extent along the axis.
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

}  // namespace
}  // namespace dentsim
