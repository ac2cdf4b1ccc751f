// Bring to tooth: the drill put over the professional's first contact, clear of the tissue by the clearance, on a flat block where the distances are known.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sim/bring_to_tooth.h"
#include "sim_fixtures.h"

namespace dentsim {
namespace {

constexpr double kR = 0.1;  // the round head's radius [mm]

// A path of the drill going down `axis` (the tool's -z turned onto it) from 1 mm above the block's
// surface at its centre to 0.3 mm into it, a sample per 0.01 mm, 1 ms apart.
PenPath descent(const test::Block& b, const Quat& tilt) {
  PenPath path;
  const Vec3 down = tilt.rotate(Vec3{0, 0, -1});
  const Vec3 entry{0.8, 0.8, b.surface_mm};
  for (int i = 0; i <= 130; ++i) {
    PenSample s;
    s.t_s = i * 0.001;
    s.pose.rotation = tilt;
    s.pose.position = entry + down * (0.01 * i - 1.0);  // the grip is the tip here
    path.samples.push_back(s);
  }
  return path;
}

TEST(BringToTooth, AnUprightBurStopsTheClearanceAboveTheSurfaceItFirstTouched) {
  const test::Block b = test::flatBlock(Material::Enamel);
  const ToolModel bur = test::sphereBur(kR, 0.01);
  const auto got = bringToTooth(descent(b, Quat{}), bur, b.volume, b.frame, 0.3);
  ASSERT_TRUE(got.has_value());
  // The first sample in tissue: the tip a little under the surface (phi > 0 needs the tip past the
  // half-filled boundary), so the 101st sample at the latest (the tip 0.01 mm under).
  EXPECT_GE(got->first_contact_s, 0.0995);
  EXPECT_LE(got->first_contact_s, 0.1015);
  // Backed off until no point is in tissue, then 0.3 mm more: the tip 0.3 mm over the surface,
  // within the back-off's step (a quarter voxel) and the boundary's half voxel.
  EXPECT_NEAR(got->grip.position.z, b.surface_mm + 0.3, 0.5 * test::Block::kVoxel + 0.25 * test::Block::kVoxel);
  EXPECT_NEAR(got->grip.position.x, 0.8, 1e-9);
  EXPECT_NEAR(got->grip.position.y, 0.8, 1e-9);
  EXPECT_FALSE(shellTouches(bur, got->grip, b.volume, b.frame));
  // One lower-key press of 0.1 mm three times, and a fourth: contact after the clearance is spent.
  Pose lowered = got->grip;
  lowered.position.z -= 0.3 + test::Block::kVoxel;
  EXPECT_TRUE(shellTouches(bur, lowered, b.volume, b.frame));
}

TEST(BringToTooth, ATiltedBurBacksOffAlongItsOwnAxis) {
  const test::Block b = test::flatBlock(Material::Dentin);
  const ToolModel bur = test::sphereBur(kR, 0.01);
  const Quat tilt = Quat::fromAxisAngle(Vec3{1, 0, 0}, std::numbers::pi / 4);  // 45 degrees about x
  const auto got = bringToTooth(descent(b, tilt), bur, b.volume, b.frame, 0.3);
  ASSERT_TRUE(got.has_value());
  const Vec3 up = tilt.rotate(Vec3{0, 0, 1});
  // The grip on the path's line (backed along the axis it came down) ...
  const Vec3 from_entry = got->grip.position - Vec3{0.8, 0.8, b.surface_mm};
  EXPECT_NEAR(norm(from_entry - up * dot(from_entry, up)), 0.0, 1e-9);
  // ... and the sphere's lowest point 0.3 mm along that axis above the surface: height 0.3 cos 45
  // for the sphere's centre moved 0.3 mm along the tilted axis.
  const double centre_z = got->grip.position.z + kR * up.z;  // the head's centre, kR up the tool axis
  EXPECT_NEAR(centre_z - kR - b.surface_mm, 0.3 * std::cos(std::numbers::pi / 4), 0.75 * test::Block::kVoxel);
}

TEST(BringToTooth, APathThatNeverTouchesOrHasNoDrillGivesNothing) {
  const test::Block b = test::flatBlock(Material::Enamel);
  const ToolModel bur = test::sphereBur(kR, 0.01);
  PenPath above = descent(b, Quat{});
  above.samples.resize(50);  // stops 0.5 mm over the surface
  EXPECT_FALSE(bringToTooth(above, bur, b.volume, b.frame, 0.3).has_value());
  PenPath mirror_only = descent(b, Quat{});
  for (PenSample& s : mirror_only.samples) s.pen = PenRole::Mirror;
  EXPECT_FALSE(bringToTooth(mirror_only, bur, b.volume, b.frame, 0.3).has_value());
}

}  // namespace
}  // namespace dentsim
