// Tests of the course's restorative paths on the built-in molar at level 7: each professional's cut drilled by the scripted pen removes tissue where its class says and nowhere else; the pocket planner's pieces on small cases.
#include "sim/restorative_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim/course_paths.h"
#include "sim/session_run.h"
#include "sim_fixtures.h"

namespace dentsim {
namespace {

using test::molar;

// Every voxel whose fill went down: its centre [mm], its initial material and how much it lost [mm^3].
struct Removed {
  Vec3 centre;
  Material material;
  double mm3;
};

std::vector<Removed> removedVoxels(const ToothVolume& before, const ToothVolume& after) {
  std::vector<Removed> out;
  const uint32_t n = before.voxels.dim();
  const double v = before.frame.voxel_mm;
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const Voxel a = before.voxels.voxel(x, y, z), b = after.voxels.voxel(x, y, z);
        if (voxelFill(a) == 0 || voxelFill(b) >= voxelFill(a)) continue;
        out.push_back({{before.frame.origin_mm[0] + (x + 0.5) * v, before.frame.origin_mm[1] + (y + 0.5) * v,
                        before.frame.origin_mm[2] + (z + 0.5) * v},
                       voxelMaterial(a),
                       double(voxelFill(a) - voxelFill(b)) / DS_FILL_FULL * before.frame.voxelVolumeMm3()});
      }
  return out;
}

// The tooth after the scripted pen plays `path` with `bur` under the default parameters.
ToothVolume drilled(const PenPath& path, const std::string& bur) {
  ToothVolume tooth = molar();
  ScriptedSessionOptions so;
  so.drill_tool = bur;
  auto run = recordScriptedSession(tooth, defaultSimParams(), path, "", SessionInfo{}, so);
  EXPECT_TRUE(run.ok()) << run.message();
  return tooth;
}

// ---- the pocket planner's pieces -------------------------------------------------------------------------

TEST(PocketPlanner, BurHeadsComeFromTheCatalog) {
  auto round = burHead("round_bur_014");
  ASSERT_TRUE(round.ok()) << round.message();
  EXPECT_TRUE(round->round);
  EXPECT_DOUBLE_EQ(round->radius_mm, 0.7);
  EXPECT_DOUBLE_EQ(round->length_mm, 1.4);
  auto fissure = burHead("fissure_bur_010");
  ASSERT_TRUE(fissure.ok()) << fissure.message();
  EXPECT_FALSE(fissure->round);
  EXPECT_DOUBLE_EQ(fissure->radius_mm, 0.5);
  EXPECT_DOUBLE_EQ(fissure->length_mm, 4.0);
  auto mirror = burHead("mirror_size4");
  ASSERT_FALSE(mirror.ok());
  EXPECT_NE(mirror.message().find("mirror_size4"), std::string::npos);
}

TEST(PocketPlanner, AxisFrameIsRightHandedAndItsRotationCarriesTheBurAlongTheAxis) {
  // Vertical: the identity, exactly, so that a vertical path's poses are the class I path's.
  const AxisFrame up = AxisFrame::along({1, 2, 3}, {0, 0, 2}, {1, 0, 0});
  EXPECT_EQ(up.rotation(), Quat{});
  EXPECT_EQ(up.at(1, 2, 3), (Vec3{2, 4, 6}));
  EXPECT_DOUBLE_EQ(up.height({0, 0, 5}), 2.0);
  // From buccal, tilted down: e_u stays mesiodistal, e_v = axis x e_u points occlusally.
  const AxisFrame buccal = AxisFrame::along({0, 0, 0}, {0, -0.96, -0.26}, {1, 0, 0});
  EXPECT_NEAR(norm(buccal.axis), 1.0, 1e-12);
  EXPECT_NEAR(dot(buccal.e_u, buccal.axis), 0.0, 1e-12);
  EXPECT_NEAR(norm(cross(buccal.e_u, buccal.e_v) - buccal.axis), 0.0, 1e-12);
  EXPECT_GT(buccal.e_v.z, 0.9);
  EXPECT_NEAR(norm(buccal.rotation().rotate({0, 0, 1}) - buccal.axis), 0.0, 1e-12);
}

TEST(PocketPlanner, RayMeetsAFlatSurfaceWhereItIs) {
  const test::Block b = test::flatBlock(Material::Dentin);  // surface z = 0.8 mm
  TissueRay ray(b.volume, b.frame);
  auto down = ray.first({0.8, 0.8, 1.5}, {0, 0, -1}, 1.5);
  ASSERT_TRUE(down.has_value());
  EXPECT_NEAR(down->distance_mm, 0.7, 0.5 * test::Block::kVoxel);
  EXPECT_EQ(down->material, Material::Dentin);
  EXPECT_FALSE(ray.first({0.8, 0.8, 1.5}, {0, 0, 1}, 1.0).has_value());  // away from it: nothing
}

TEST(PocketPlanner, APocketInAFlatBlockStaysInItsColumnsAndAboveItsFloor) {
  const test::Block b = test::flatBlock(Material::Dentin);  // surface z = 0.8 mm, 1.6 mm a side
  const AxisFrame axis = AxisFrame::along({0.8, 0.8, 0.0}, {0, 0, 1}, {1, 0, 0});
  // Three columns in a row 0.2 mm apart, 0.3 mm deep; one more beside them 0.1 mm deep.
  const std::vector<PocketColumn> columns = {{-0.2, 0, 0.5}, {0, 0, 0.5}, {0.2, 0, 0.5}, {0.2, 0.2, 0.7}};
  PocketSettings s;
  s.grid_mm = 0.2;
  s.layer_mm = 0.1;
  s.press_mm = 0.05;
  auto plan = pocketPath(b.volume, b.frame, defaultSimParams(), "round_bur_008", axis, columns, s);
  ASSERT_TRUE(plan.ok()) << plan.message();
  EXPECT_GT(plan->positions, 0);
  EXPECT_GE(plan->layers, 3);  // 0.3 mm of tissue in 0.1 mm layers
  // The ball's volume in tissue bounds the plan: four balls of 0.4 mm at 0.8 mm..0.5 mm and the
  // troughs between them are far less than the block of 1.2 x 1.0 x 0.3 mm around them.
  EXPECT_GT(plan->planned_mm3, 0.0);
  EXPECT_LT(plan->planned_mm3, 1.2 * 1.0 * 0.7);
  EXPECT_TRUE(std::is_sorted(plan->path.samples.begin(), plan->path.samples.end(),
                             [](const PenSample& p, const PenSample& q) { return p.t_s < q.t_s; }));
  for (const PenSample& sample : plan->path.samples) {
    const Vec3 tip = sample.pose.position - Vec3{0, 0, s.grip_mm};
    EXPECT_EQ(sample.pose.rotation, Quat{});
    EXPECT_GE(tip.z, 0.5 - 1e-9) << sample.t_s;  // never below the deepest floor
    if (tip.z < 0.8 - 1e-9) {                     // in the tissue: over a column
      EXPECT_GE(tip.x, 0.6 - 1e-9) << sample.t_s;
      EXPECT_LE(tip.x, 1.0 + 1e-9) << sample.t_s;
      EXPECT_GE(tip.y, 0.8 - 1e-9) << sample.t_s;
      EXPECT_LE(tip.y, 1.0 + 1e-9) << sample.t_s;
      if (tip.y > 0.8 + 1e-9) {
        EXPECT_GE(tip.z, 0.7 - 1e-9) << sample.t_s;  // the shallow column's floor
      }
    }
  }
  EXPECT_EQ(plan->path.samples.front().pedal, 0.0);
  EXPECT_EQ(plan->path.samples.back().pedal, 0.0);
  EXPECT_FALSE(pocketPath(b.volume, b.frame, defaultSimParams(), "round_bur_008", axis, {}, s).ok());
  EXPECT_FALSE(pocketPath(b.volume, b.frame, defaultSimParams(), "mirror_size4", axis, columns, s).ok());
}

// ---- the preparations on the molar ------------------------------------------------------------------------

TEST(RestorativePaths, ClassTwoOpensTheMesialSurfaceAboveTheCejAndKeepsToItsOutline) {
  const std::string bur = "fissure_bur_010";
  const Class2Settings s;
  auto plan = class2CavityPath(molar().voxels, molar().frame, defaultSimParams(), bur, s);
  ASSERT_TRUE(plan.ok()) << plan.message();
  const double v = molar().frame.voxel_mm, r = 0.5;
  // The molar's CEJ lies at z = 0 (assets/README.md); the enamel is a voxel thick some way above it.
  EXPECT_NEAR(plan->mesial_cej_z, 0.0, 0.5);
  EXPECT_DOUBLE_EQ(plan->gingival_floor_z, plan->mesial_cej_z + s.gingival_above_cej_mm);
  EXPECT_LT(plan->mesial_surface_x, -4.0);  // the crown is about 11 mm mesiodistally, centred on x = 0
  EXPECT_NEAR(plan->axial_wall_x - plan->mesial_surface_x, s.box_depth_mm, 1e-12);
  const std::vector<Removed> removed = removedVoxels(molar(), drilled(plan->cut.path, bur));
  double mesial_box = 0.0, dentin = 0.0;
  for (const Removed& c : removed) {
    // The box: on the mesial surface, between the gingival floor and well under the marginal ridge.
    if (c.centre.x < plan->mesial_surface_x + 0.3 && c.centre.z < plan->fossa_surface_z - 1.0) mesial_box += c.mm3;
    if (c.material == Material::Dentin) dentin += c.mm3;
    EXPECT_NE(c.material, Material::Pulp);
    EXPECT_GE(c.centre.z, plan->gingival_floor_z - v) << "below the gingival floor";
    EXPECT_GT(c.centre.z, plan->mesial_cej_z + 0.5) << "at the CEJ";
    EXPECT_LE(c.centre.x, plan->fossa_mm.x + s.distal_reach_mm + r + v) << "distal of the outline";
    EXPECT_LE(std::abs(c.centre.y - plan->fossa_mm.y), plan->box_half_width_mm + v) << "beside the box";
    // Out of the box, only the occlusal part: no deeper than its floor, no wider than the isthmus.
    if (c.centre.x > plan->axial_wall_x + v) {
      EXPECT_GE(c.centre.z, plan->occlusal_floor_z - v) << c.centre.x;
      EXPECT_LE(std::abs(c.centre.y - plan->fossa_mm.y), 0.5 * s.isthmus_width_mm + v) << c.centre.x;
    }
  }
  EXPECT_GT(mesial_box, 1.0);  // mm^3: the box's lower half, a wall 2.6 mm wide
  EXPECT_GT(dentin, 1.0);      // the floors lie in dentin
}

TEST(RestorativePaths, ClassFiveCutsOnlyTheBuccalSurfaceJustAboveTheCej) {
  const std::string bur = "round_bur_010";
  const Class5Settings s;
  auto plan = class5CavityPath(molar().voxels, molar().frame, defaultSimParams(), bur, s);
  ASSERT_TRUE(plan.ok()) << plan.message();
  const double v = molar().frame.voxel_mm;
  EXPECT_NEAR(plan->buccal_cej_z, 0.0, 0.5);
  // The buccal surface just above the CEJ faces buccally and a little down (the cervical bulge).
  EXPECT_LT(plan->normal.y, -0.9);
  EXPECT_LT(std::abs(plan->normal.x), 0.1);
  EXPECT_EQ(plan->axis, plan->normal);  // no axis given: the bur along the normal
  EXPECT_NEAR(norm(plan->cut.path.samples.front().pose.rotation.rotate({0, 0, 1}) - plan->axis), 0.0, 1e-9);
  const std::vector<Removed> removed = removedVoxels(molar(), drilled(plan->cut.path, bur));
  double enamel = 0.0, dentin = 0.0;
  for (const Removed& c : removed) {
    EXPECT_NE(c.material, Material::Pulp);
    (c.material == Material::Enamel ? enamel : dentin) += c.mm3;
    EXPECT_LT(c.centre.y, plan->centre_mm.y + s.depth_mm + v) << "deeper than the axial wall";
    EXPECT_GE(c.centre.z, plan->buccal_cej_z - v) << "below the CEJ";
    EXPECT_LE(c.centre.z, plan->buccal_cej_z + s.above_cej_mm + s.height_mm + 2 * v) << "above the outline";
    EXPECT_LE(std::abs(c.centre.x - plan->centre_mm.x), 0.5 * s.width_mm + v) << "beside the outline";
  }
  EXPECT_GT(enamel, 0.2);  // mm^3: through the thin cervical enamel
  EXPECT_GT(dentin, 0.2);  // into the dentin under it
  // A given axis is the bur's.
  Class5Settings level = s;
  level.axis = {0, -1, 0};
  auto straight = class5CavityPath(molar().voxels, molar().frame, defaultSimParams(), bur, level);
  ASSERT_TRUE(straight.ok()) << straight.message();
  EXPECT_EQ(straight->axis, (Vec3{0, -1, 0}));
  level.axis = {0, 1, 0};  // from lingual: not this preparation
  EXPECT_FALSE(class5CavityPath(molar().voxels, molar().frame, defaultSimParams(), bur, level).ok());
}

TEST(RestorativePaths, AccessOpensThePulpChamberThroughTheOcclusalCentreAndTakesItsRoof) {
  const std::string bur = "round_bur_014";
  auto plan = accessCavityPath(molar().voxels, molar().frame, defaultSimParams(), bur);
  ASSERT_TRUE(plan.ok()) << plan.message();
  const double v = molar().frame.voxel_mm;
  // The horns reach 1.3 to 2.0 mm above the CEJ (assets/README.md, the generator's horn tips).
  EXPECT_NEAR(plan->pulp_top_z, 2.0, 0.4);
  EXPECT_LT(std::abs(plan->centre_mm.x), 1.0);
  EXPECT_LT(std::abs(plan->centre_mm.y), 1.0);
  const ToothVolume after = drilled(plan->cut.path, bur);
  const std::vector<Removed> removed = removedVoxels(molar(), after);
  double pulp = 0.0, dentin = 0.0;
  for (const Removed& c : removed) {
    if (c.material == Material::Pulp) pulp += c.mm3;
    if (c.material == Material::Dentin) dentin += c.mm3;
    const double du = (c.centre.x - plan->centre_mm.x) / (plan->half_x_mm + v),
                 dv = (c.centre.y - plan->centre_mm.y) / (plan->half_y_mm + v);
    EXPECT_LE(du * du + dv * dv, 1.0) << "outside the outline at " << c.centre.x << ", " << c.centre.y;
    EXPECT_GE(c.centre.z, plan->lowest_floor_z - v) << "below the deepest floor";
  }
  EXPECT_GT(pulp, 0.1);     // mm^3: the chamber is open
  EXPECT_GT(dentin, 10.0);  // the roof: dentin from the DEJ down to the chamber over the whole outline
  // Over the outline's centre nothing is left above the pulp that was there: the first voxel of
  // more than half fill, looking down, lies no higher than the pulp's top was.
  const double x = plan->centre_mm.x, y = plan->centre_mm.y;
  const auto ix = uint32_t((x - after.frame.origin_mm[0]) / v), iy = uint32_t((y - after.frame.origin_mm[1]) / v);
  for (int64_t z = after.voxels.dim() - 1; z >= 0; --z)
    if (voxelFill(after.voxels.voxel(ix, iy, uint32_t(z))) > DS_FILL_FULL / 2) {
      EXPECT_LE(after.frame.origin_mm[2] + (double(z) + 0.5) * v, plan->pulp_top_z);
      break;
    }
}

TEST(CoursePaths, EveryBuiltinPathHasAnExpertAndTheNamesAreChecked) {
  const SimParams params = defaultSimParams();
  EXPECT_EQ(builtinPathNames(), "class1_cavity, class2_cavity, class5_cavity, access_cavity, caries_removal, crown_prep");
  for (const char* name : kBuiltinPaths) {
    Exercise e;
    e.path = name;
    e.bur = std::string(name) == "class2_cavity" ? "fissure_bur_010" : std::string(name) == "crown_prep" ? "chamfer_bur_016" : "round_bur_010";
    if (std::string(name) == "class5_cavity") e.insertion_axis = {0, -1, 0};
    auto path = expertPath(e, molar().voxels, molar().frame, params);
    ASSERT_TRUE(path.ok()) << name << ": " << path.message();
    EXPECT_GT(path->samples.size(), 10u) << name;
  }
  Exercise unknown;
  unknown.path = "class3_cavity";
  auto none = expertPath(unknown, molar().voxels, molar().frame, params);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("class1_cavity, class2_cavity"), std::string::npos) << none.message();
  // A cavity without a built-in path has no scripted attempt; a caries removal needs none.
  Exercise pathless;
  EXPECT_FALSE(taskAttemptPath(pathless, Attempt::Expert, molar().voxels, molar().frame, params).ok());
}

TEST(CoursePaths, TheFaultsChangeTheExpertsPathAsNamed) {
  const SimParams params = defaultSimParams();
  Exercise e;
  e.path = "class5_cavity";
  e.insertion_axis = {0, -1, 0};
  auto expert = taskAttemptPath(e, Attempt::Expert, molar().voxels, molar().frame, params);
  auto slow = taskAttemptPath(e, Attempt::Slow, molar().voxels, molar().frame, params);
  auto undercut = taskAttemptPath(e, Attempt::Undercut, molar().voxels, molar().frame, params);
  auto overcut = taskAttemptPath(e, Attempt::Overcut, molar().voxels, molar().frame, params);
  auto trench = taskAttemptPath(e, Attempt::Trench, molar().voxels, molar().frame, params);
  ASSERT_TRUE(expert.ok() && slow.ok() && undercut.ok() && overcut.ok() && trench.ok());
  EXPECT_DOUBLE_EQ(slow->samples.back().t_s, 3.0 * expert->samples.back().t_s);
  EXPECT_LT(undercut->samples.back().t_s, 0.5 * expert->samples.back().t_s);
  // The wider outline reaches further across the buccal surface (x) than the expert's.
  auto reach = [](const PenPath& p) {
    double most = 0.0;
    for (const PenSample& s : p.samples)
      if (s.pedal > 0) most = std::max(most, std::abs(s.pose.position.x - p.samples.front().pose.position.x));
    return most;
  };
  EXPECT_GT(reach(*overcut), reach(*expert) + 0.5);
  // The trench is cut from above, away from the buccal surface.
  EXPECT_EQ(trench->samples.front().pose.rotation, Quat{});
}

}  // namespace
}  // namespace dentsim
