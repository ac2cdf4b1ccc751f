// Contact physics against analytic values: the spring force of a sphere in a flat block, friction, and the moment r x F.
#include "sim/contact.h"

#include <gtest/gtest.h>

#include <tuple>
#include <vector>

#include "sim/point_shell.h"
#include "sim/voxel_field.h"
#include "sim_fixtures.h"

namespace dentsim {
namespace {

using test::Block;
using test::capSpringForce;
using test::flatBlock;
using test::sphereBur;

constexpr double kR = 0.5;  // bur radius [mm]

// The bur's tool pose with its tip `depth` below the block's surface, at (x, y).
Pose pressed(const Block& b, double depth, double x = 0.8, double y = 0.8) {
  return Pose{{x, y, b.surface_mm - depth}, Quat{}};
}

// A 0.5 mm sphere pressed 0.03 mm into a flat block of `tissue`, with its contact set.
struct Pressed {
  explicit Pressed(Material tissue)
      : block(flatBlock(tissue)), field(block.volume, block.frame), bur(sphereBur(kR, 0.03)), finder(bur.shell.size()) {
    pose = pressed(block, 0.03);
    auto found = finder.find(field, bur.shell, pose);
    contacts.assign(found.begin(), found.end());
  }
  Block block;
  VoxelField field;
  ToolModel bur;
  ContactFinder finder;
  SimParams params = defaultSimParams();
  Pose pose;
  std::vector<ContactPoint> contacts;
};

TEST(VoxelField, FlatSurfaceFieldIsZeroOnThePlaneWithUnitGradient) {
  Block b = flatBlock(Material::Enamel);
  VoxelField field(b.volume, b.frame);
  // Across the surface (between the last solid and first empty voxel centres) the field is linear.
  for (double dz : {-0.4, -0.1, 0.0, 0.25, 0.45}) {
    const Vec3 u = field.toVoxel({0.8, 0.8, b.surface_mm + dz * Block::kVoxel});
    const FieldSample s = field.sample(u, true);
    EXPECT_NEAR(s.phi, -dz, 1e-12) << dz;
    EXPECT_NEAR(s.gradient.z, -1.0, 1e-12);
    EXPECT_EQ(s.material, dz < 0 ? Material::Enamel : Material::Empty) << "the tissue is named inside it only";
  }
  EXPECT_EQ(field.sample(field.toVoxel({0.8, 0.8, 1.5})).material, Material::Empty);
  EXPECT_FALSE(field.chunksEmpty({0, 0, 0}, {10, 10, 10}));
}

TEST(Contact, FlatEnamelBlockGivesThePredictedSpringForceAlongTheNormal) {
  Block b = flatBlock(Material::Enamel);
  VoxelField field(b.volume, b.frame);
  const ToolModel bur = sphereBur(kR, 0.02);
  SimParams params = defaultSimParams();
  const double k = params.tissue(Material::Enamel).stiffness_n_per_mm3;
  ContactFinder finder(bur.shell.size());
  // Shallow (the field's linear band), a few voxels, and deep enough that points must march out.
  for (double depth : {0.006, 0.02, 0.05, 0.1}) {
    const Pose pose = pressed(b, depth);
    auto contacts = finder.find(field, bur.shell, pose);
    ASSERT_GT(contacts.size(), 0u);
    const ContactForce f = contactForce(contacts, params, ToolMotion{pose.position, {}, {}});
    const double expected = capSpringForce(k, kR, depth);
    EXPECT_NEAR(f.wrench.force.z, expected, 0.05 * expected) << "depth " << depth;
    // In the normal direction: the sideways part is a rounding of the sampling, not a force.
    EXPECT_LT(std::hypot(f.wrench.force.x, f.wrench.force.y), 0.01 * f.wrench.force.z) << depth;
    for (const ContactPoint& cp : contacts) EXPECT_GT(cp.normal.z, 0.99);
  }
}

TEST(Contact, SpringForceScalesWithTheTissueStiffness) {
  const ToolModel bur = sphereBur(kR, 0.03);
  SimParams params = defaultSimParams();
  double per_stiffness[2];
  int i = 0;
  for (Material m : {Material::Enamel, Material::Caries}) {
    Block b = flatBlock(m);
    VoxelField field(b.volume, b.frame);
    ContactFinder finder(bur.shell.size());
    const Pose pose = pressed(b, 0.03);
    const ContactForce f = contactForce(finder.find(field, bur.shell, pose), params, ToolMotion{pose.position, {}, {}});
    per_stiffness[i++] = f.wrench.force.z / params.tissue(m).stiffness_n_per_mm3;
  }
  EXPECT_NEAR(per_stiffness[0], per_stiffness[1], 1e-9 * per_stiffness[0]);
}

TEST(Contact, FrictionOpposesSlidingWithTheCoulombMagnitude) {
  const Pressed p(Material::Dentin);
  const auto& [contacts, params, pose] = std::tie(p.contacts, p.params, p.pose);
  const double mu = params.tissue(Material::Dentin).friction;
  for (const Vec3 v : {Vec3{20, 0, 0}, Vec3{0, -15, 0}, Vec3{12, 9, 0}}) {
    const ContactForce f = contactForce(contacts, params, ToolMotion{pose.position, v, {}});
    const Vec3 tangential{f.wrench.force.x, f.wrench.force.y, 0};
    EXPECT_LT(dot(tangential, v), 0) << "friction must oppose the sliding";
    // Well above the slip speed, every point's friction is mu times its normal force.
    EXPECT_NEAR(norm(tangential), mu * f.normal_force_n, 0.01 * mu * f.normal_force_n);
    EXPECT_NEAR(dot(normalized(tangential), normalized(v)), -1.0, 1e-6);
  }
  // At rest there is no friction at all.
  const ContactForce rest = contactForce(contacts, params, ToolMotion{pose.position, {}, {}});
  EXPECT_LT(std::hypot(rest.wrench.force.x, rest.wrench.force.y), 0.01 * rest.wrench.force.z);
}

TEST(Contact, DampingGrowsWithTheSpeedIntoTheTissueAndNeverPulls) {
  const Pressed p(Material::Enamel);
  const auto& [contacts, params, pose] = std::tie(p.contacts, p.params, p.pose);
  const double alpha = params.tissue(Material::Enamel).damping_s_per_mm;
  const double spring = contactForce(contacts, params, ToolMotion{pose.position, {}, {}}).wrench.force.z;
  // Moving in at v: Hunt-Crossley scales every point's spring by (1 + alpha v).
  const double in = contactForce(contacts, params, ToolMotion{pose.position, {0, 0, -100}, {}}).wrench.force.z;
  EXPECT_NEAR(in, spring * (1 + alpha * 100), 1e-9 * spring);
  const ContactForce out = contactForce(contacts, params, ToolMotion{pose.position, {0, 0, 1e6}, {}});
  EXPECT_EQ(out.wrench.force.z, 0.0) << "leaving fast: the damper cancels the spring but never pulls";
  EXPECT_EQ(out.impact_speed_mm_s, 0.0) << "leaving: no point moves into tissue";
  const ContactForce in_fast = contactForce(contacts, params, ToolMotion{pose.position, {0, 0, -250}, {}});
  EXPECT_NEAR(in_fast.impact_speed_mm_s, 250.0, 1e-9);
}

TEST(Contact, MomentAboutAnOffAxisGripIsRCrossF) {
  Block b = flatBlock(Material::Enamel);
  VoxelField field(b.volume, b.frame);
  const Vec3 grip_local{3.0, -1.5, 12.0};
  const ToolModel bur = sphereBur(kR, 0.02, grip_local);
  SimParams params = defaultSimParams();
  ContactFinder finder(bur.shell.size());
  // Tilt the tool about the sphere's centre, so the grip swings off the contact's axis.
  const Quat tilt = Quat::fromAxisAngle({1, 1, 0}, 0.35);
  const Vec3 centre{0.8, 0.8, b.surface_mm - 0.04 + kR};
  const Pose pose{centre - tilt.rotate(Vec3{0, 0, kR}), tilt};
  const Vec3 grip = pose.apply(grip_local);
  const ContactForce f = contactForce(finder.find(field, bur.shell, pose), params, ToolMotion{grip, {}, {}});
  // Every point pushes along +z and the cap is symmetric about the vertical through the centre, so
  // the resultant acts along that line: M = (centre - grip) x F.
  const Vec3 expected = cross(centre - grip, f.wrench.force);
  ASSERT_GT(norm(expected), 1.0);
  EXPECT_LT(norm(f.wrench.moment - expected), 0.01 * norm(expected));
}

TEST(Contact, FrictionLinearizationIsTheDerivativeOfTheFrictionWrench) {
  // Without Hunt-Crossley damping the normal forces do not depend on the velocity, and below the
  // slip speed friction is viscous: the wrench is linear in the tool's velocity, so the matrix the
  // proxy step uses must equal minus its derivative, column by column, to rounding.
  SimParams params = defaultSimParams();
  for (TissueParams& t : params.tissues) t.damping_s_per_mm = 0.0;
  std::vector<ContactPoint> contacts;
  const Material tissues[] = {Material::Enamel, Material::Dentin, Material::Caries};
  uint64_t seed = 12345;
  auto uniform = [&](double lo, double hi) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * double(seed >> 11) * 0x1.0p-53;
  };
  for (int i = 0; i < 7; ++i) {
    ContactPoint cp;
    cp.position = {uniform(-0.6, 0.6), uniform(-0.6, 0.6), uniform(-0.6, 0.6)};
    cp.normal = normalized(Vec3{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)});
    cp.depth_mm = uniform(0.001, 0.05);
    cp.area_mm2 = uniform(0.0005, 0.001);
    cp.material = tissues[i % 3];
    contacts.push_back(cp);
  }
  ToolMotion motion{{0.1, -0.2, 0.3}, {0.2, -0.1, 0.15}, {0.1, 0.2, -0.15}};
  const ContactForce base = contactForce(contacts, params, motion);
  ASSERT_GT(base.friction_damping[0], 0.0);
  constexpr double h = 1e-4;
  for (int j = 0; j < 6; ++j) {
    ToolMotion plus = motion, minus = motion;
    Vec3& vp = j < 3 ? plus.linear : plus.angular;
    Vec3& vm = j < 3 ? minus.linear : minus.angular;
    vp[j % 3] += h;
    vm[j % 3] -= h;
    const Wrench wp = contactForce(contacts, params, plus).wrench, wm = contactForce(contacts, params, minus).wrench;
    const double dw[6] = {wp.force.x - wm.force.x, wp.force.y - wm.force.y, wp.force.z - wm.force.z,
                          wp.moment.x - wm.moment.x, wp.moment.y - wm.moment.y, wp.moment.z - wm.moment.z};
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(base.friction_damping[size_t(6 * i + j)], -dw[i] / (2 * h), 1e-9 + 1e-6 * std::abs(dw[i] / h))
          << "row " << i << " column " << j;
  }
}

TEST(Contact, ClustersInEmptyChunksAreSkippedWithoutMissingContacts) {
  Block b = flatBlock(Material::Enamel, 8);  // a thin layer: most chunks empty
  VoxelField field(b.volume, b.frame);
  PointShellParams spacing;
  auto bur = loadToolModel("round_bur_010", spacing);
  ASSERT_TRUE(bur.ok()) << bur.message();
  ContactFinder finder(bur->shell.size());
  ContactStats stats;
  const Pose pose{{0.8, 0.8, b.surface_mm - 0.02}, Quat{}};
  auto contacts = finder.find(field, bur->shell, pose, &stats);
  EXPECT_GT(stats.clusters_skipped, 0u);
  EXPECT_LT(stats.points_tested, bur->shell.size());
  // The same contacts as testing every point.
  size_t brute = 0;
  for (size_t i = 0; i < bur->shell.size(); ++i)
    if (field.sample(field.toVoxel(pose.apply(bur->shell.positions[i]))).phi > 0) ++brute;
  EXPECT_EQ(contacts.size(), brute);
  EXPECT_GT(brute, 0u);
}

}  // namespace
}  // namespace dentsim
