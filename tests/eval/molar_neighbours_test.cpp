// Tests of the built-in molar between its neighbours: the neighbours beside the molar, the molar as builtin:molar has it, replay's name for it, and the class II task's expert that leaves them whole where the over-cutter nicks the premolar.
//
// Level 7 (0.23 mm voxels over the three teeth): the contacts and the box's clearance already show,
// and each drill takes seconds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "eval/cut_score.h"
#include "eval/task_tooth.h"
#include "eval/tooth_diff.h"
#include "io/session_file.h"
#include "sim/builtin_tooth.h"
#include "sim/course_paths.h"
#include "sim/restorative_paths.h"
#include "sim/session_run.h"
#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"

namespace dentsim {
namespace {

constexpr int kLevel = 7;

const ToothVolume& neighboursTooth() {
  static const ToothVolume tooth = [] {
    auto t = builtinTooth(kBuiltinMolarNeighboursTooth, kLevel);
    EXPECT_TRUE(t.ok()) << t.message();
    return std::move(t).value();
  }();
  return tooth;
}

// Per material: voxel count, volume [mm^3] and x range of the voxel centres [mm].
struct Census {
  std::array<uint64_t, DS_MATERIAL_COUNT> voxels{};
  std::array<double, DS_MATERIAL_COUNT> mm3{};
  std::array<double, DS_MATERIAL_COUNT> lo_x{}, hi_x{};
  uint64_t neighbour_mesial = 0, neighbour_distal = 0;  // neighbour voxels mesial / distal of x = 0
  uint64_t mesial_fill = 0, distal_fill = 0;            // their fill [1/31 voxel]
};
Census census(const ToothVolume& t) {
  Census c;
  c.lo_x.fill(HUGE_VAL);
  c.hi_x.fill(-HUGE_VAL);
  const double v = t.frame.voxel_mm;
  t.voxels.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelFill(b.value) == 0) return;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel vox = b.at(i);
      if (voxelFill(vox) == 0) continue;
      const size_t m = size_t(voxelMaterial(vox));
      const double x = t.frame.origin_mm[0] + (b.coord.x * DS_BRICK_DIM + (i & 7u) + 0.5) * v;
      ++c.voxels[m];
      c.mm3[m] += double(voxelFill(vox)) / DS_FILL_FULL * v * v * v;
      c.lo_x[m] = std::min(c.lo_x[m], x);
      c.hi_x[m] = std::max(c.hi_x[m], x);
      if (voxelMaterial(vox) != Material::Neighbour) continue;
      ++(x < 0 ? c.neighbour_mesial : c.neighbour_distal);
      (x < 0 ? c.mesial_fill : c.distal_fill) += voxelFill(vox);
    }
  });
  return c;
}

constexpr size_t kN = size_t(Material::Neighbour);

TEST(MolarNeighboursTooth, NeighboursStandMesialAndDistalOfTheMolar) {
  const ToothVolume& t = neighboursTooth();
  const Census c = census(t);
  // The molar's extent over its own tissues.
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (Material m : kTissues)
    if (isToothTissue(m)) lo = std::min(lo, c.lo_x[size_t(m)]), hi = std::max(hi, c.hi_x[size_t(m)]);
  EXPECT_NEAR(hi - lo, 11.0, 0.6) << "the molar, 11 mm mesiodistally";
  // Both neighbours, whole: the premolar about 420 mm^3, the second molar about 720 (the meshes'
  // volumes, tests/model), each within 3% (a voxel's rounding over their surfaces).
  ASSERT_GT(c.neighbour_mesial, 0u);
  ASSERT_GT(c.neighbour_distal, 0u);
  const double v3 = std::pow(t.frame.voxel_mm, 3);
  const double mesial_mm3 = double(c.mesial_fill) / DS_FILL_FULL * v3, distal_mm3 = double(c.distal_fill) / DS_FILL_FULL * v3;
  EXPECT_NEAR(mesial_mm3, 422.0, 13.0) << "the premolar";
  EXPECT_NEAR(distal_mm3, 720.0, 22.0) << "the second molar";
  // Neither reaches into the molar: every neighbour voxel lies beyond the molar's extent but for
  // the one voxel that a contact 0.1 mm wide shares with it.
  const double v = t.frame.voxel_mm;
  uint64_t inside = 0;
  t.voxels.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelFill(b.value) == 0) return;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      if (voxelMaterial(b.at(i)) != Material::Neighbour || voxelFill(b.at(i)) == 0) continue;
      const double x = t.frame.origin_mm[0] + (b.coord.x * DS_BRICK_DIM + (i & 7u) + 0.5) * v;
      if (x > lo + v && x < hi - v) ++inside;
    }
  });
  EXPECT_EQ(inside, 0u);
  EXPECT_LT(c.hi_x[kN], 16.5);
  EXPECT_GT(c.lo_x[kN], -13.0);
}

// The molar's own tissues are builtin:molar's: the same volumes within what a voxel's rounding
// moves them (the two grids differ: 0.23 mm here, 0.17 mm there), and the same occlusal centre.
TEST(MolarNeighboursTooth, TheMolarIsTheBuiltinMolar) {
  auto alone = builtinMolarTooth(kLevel);
  ASSERT_TRUE(alone.ok()) << alone.message();
  const Census a = census(*alone), n = census(neighboursTooth());
  EXPECT_EQ(a.voxels[kN], 0u);
  for (const auto& [m, share] : {std::pair{Material::Enamel, 0.03}, std::pair{Material::Dentin, 0.02},
                                 std::pair{Material::Pulp, 0.08}, std::pair{Material::Caries, 0.25}}) {
    const size_t k = size_t(m);
    EXPECT_NEAR(n.mm3[k], a.mm3[k], share * a.mm3[k]) << materialName(m);
  }
  // The frame is the molar's: the convention's axes and the molar's occlusal centre, within a voxel
  // of each grid.
  const Vec3 ca = toothOcclusalCentreMm(*alone), cn = toothOcclusalCentreMm(neighboursTooth());
  EXPECT_LT(norm(ca - cn), alone->frame.voxel_mm + neighboursTooth().frame.voxel_mm);
  EXPECT_NEAR(cn.x, 0.0, 0.5);
  EXPECT_NEAR(cn.z, 6.5, 1.0);
}

TEST(MolarNeighboursTooth, SessionsNameItSoReplayRebuildsIt) {
  EXPECT_TRUE(isBuiltinTooth(kBuiltinMolarNeighboursTooth));
  EXPECT_TRUE(isBuiltinTooth(kBuiltinMolarTooth));
  EXPECT_FALSE(isBuiltinTooth("builtin:molar_neighbours:7"));
  const std::string source = builtinToothSource(kBuiltinMolarNeighboursTooth, 6);
  EXPECT_EQ(source, "builtin:molar_neighbours:6");
  EXPECT_EQ(builtinToothLevel(source, kBuiltinMolarNeighboursTooth), 6);
  EXPECT_EQ(builtinToothLevel(source), 0) << "not the molar alone";
  EXPECT_EQ(builtinToothLevel("builtin:molar:6", kBuiltinMolarNeighboursTooth), 0);
  SessionRecording session;
  session.info.tooth_source = source;
  auto rebuilt = resolveSessionTooth(session, "/nowhere/s.dses", "");
  ASSERT_TRUE(rebuilt.ok()) << rebuilt.message();
  auto built = builtinMolarNeighboursTooth(6);
  ASSERT_TRUE(built.ok()) << built.message();
  EXPECT_TRUE(rebuilt->voxels == built->voxels);
  EXPECT_EQ(rebuilt->frame.voxel_mm, built->frame.voxel_mm);
  EXPECT_EQ(census(*rebuilt).voxels[kN], census(*built).voxels[kN]);
  // The simulator's tooth choice names it by that source, which loads as a tooth file would.
  auto loaded = loadToothFileOrAsset(source);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  EXPECT_TRUE(loaded->voxels == built->voxels);
}

// The task's attempt drilled by the scripted pen: the tooth afterwards.
ToothVolume drilled(const Task& task, Attempt attempt) {
  const ToothVolume& initial = neighboursTooth();
  const SimParams params = defaultSimParams();
  auto path = taskAttemptPath(exerciseOf(task), attempt, initial.voxels, initial.frame, params);
  EXPECT_TRUE(path.ok()) << path.message();
  ToothVolume tooth = initial;
  if (!path) return tooth;
  ScriptedSessionOptions so;
  so.drill_tool = task.drill_tool;
  auto run = recordScriptedSession(tooth, params, *path, "", SessionInfo{}, so);
  EXPECT_TRUE(run.ok()) << run.message();
  return tooth;
}

Result<Task> neighboursTask() { return builtinTask("class2_neighbours"); }

TEST(MolarNeighboursTask, IsOnTheNeighboursTooth) {
  auto task = neighboursTask();
  ASSERT_TRUE(task.ok()) << task.message();
  EXPECT_EQ(task->tooth, kBuiltinMolarNeighboursTooth);
  EXPECT_EQ(task->kind, TaskKind::Cavity);
  EXPECT_EQ(task->drill_tool, "fissure_bur_010");
  ASSERT_TRUE(task->ideal.has_value());
  EXPECT_EQ(task->ideal->path, "class2_cavity");
}

// The expert's box stops short of the premolar (its bur 0.4 mm off the premolar's nearest voxel),
// so not one neighbour voxel loses fill; without neighbours the same path opens the mesial surface.
TEST(MolarNeighboursTask, TheExpertLeavesTheNeighboursWhole) {
  auto task = neighboursTask();
  ASSERT_TRUE(task.ok()) << task.message();
  const ToothVolume& initial = neighboursTooth();
  auto plan = class2CavityPath(initial.voxels, initial.frame, defaultSimParams(), task->drill_tool);
  ASSERT_TRUE(plan.ok()) << plan.message();
  ASSERT_TRUE(plan->neighbour_x.has_value()) << "the premolar is found beside the box";
  EXPECT_NEAR(*plan->neighbour_x, -5.6, 0.5) << "at the molar's mesial contact";
  EXPECT_NEAR(plan->bur_mesial_limit_x - *plan->neighbour_x, 0.4, 1e-9);
  auto alone = builtinMolarTooth(kLevel);
  ASSERT_TRUE(alone.ok());
  auto plan_alone = class2CavityPath(alone->voxels, alone->frame, defaultSimParams(), task->drill_tool);
  ASSERT_TRUE(plan_alone.ok()) << plan_alone.message();
  EXPECT_FALSE(plan_alone->neighbour_x.has_value());

  const ToothVolume after = drilled(*task, Attempt::Expert);
  auto diff = compareTeeth(initial, after, nullptr, ZoneOptions{});
  ASSERT_TRUE(diff.ok()) << diff.message();
  const Census before_c = census(initial), after_c = census(after);
  EXPECT_EQ(after_c.voxels[kN], before_c.voxels[kN]);
  EXPECT_EQ(diff->tissue(Material::Neighbour).removed, 0u);
  EXPECT_GT(diff->total().removed, 0u);
  const double v3 = std::pow(initial.frame.voxel_mm, 3);
  const double molar_mm3 = double(diff->total().removed) / DS_FILL_FULL * v3;
  EXPECT_GT(molar_mm3, 10.0) << "the occlusal part and the box are cut";
  // The box: the molar's tissue taken mesial of the axial wall and below the occlusal floor.
  double box_mm3 = 0.0;
  const VolumeFrame& f = initial.frame;
  const uint32_t dim = initial.voxels.dim();
  for (uint32_t z = 0; z < dim; ++z)
    for (uint32_t y = 0; y < dim; ++y)
      for (uint32_t x = 0; x < dim; ++x) {
        const Voxel a = initial.voxels.voxel(x, y, z), b = after.voxels.voxel(x, y, z);
        if (voxelFill(b) >= voxelFill(a) || !isToothTissue(voxelMaterial(a))) continue;
        if (f.origin_mm[0] + (x + 0.5) * f.voxel_mm < plan->axial_wall_x &&
            f.origin_mm[2] + (z + 0.5) * f.voxel_mm < plan->occlusal_floor_z)
          box_mm3 += double(voxelFill(a) - voxelFill(b)) / DS_FILL_FULL * v3;
      }
  // At this level the scripted bur leaves most of the box's depth beside the shell (about 0.4 mm^3
  // cut there; 2.9 mm^3, down to the floor, at level 8), but it is in the box.
  EXPECT_GT(box_mm3, 0.2) << "the box is cut below the occlusal floor";
  std::printf("expert: %.2f mm^3 of the molar (%.2f in the box), %.3f mm^3 of the neighbours\n", molar_mm3, box_mm3,
              double(diff->tissue(Material::Neighbour).removed) / DS_FILL_FULL * v3);
}

// The over-cutter's box reaches 0.72 mm (0.6 box depths) past the expert's limit, 0.32 mm into the premolar.
TEST(MolarNeighboursTask, TheOvercutterNicksThePremolar) {
  auto task = neighboursTask();
  ASSERT_TRUE(task.ok()) << task.message();
  const ToothVolume& initial = neighboursTooth();
  const ToothVolume after = drilled(*task, Attempt::Overcut);
  auto diff = compareTeeth(initial, after, nullptr, ZoneOptions{});
  ASSERT_TRUE(diff.ok()) << diff.message();
  const Census before_c = census(initial), after_c = census(after);
  const uint64_t removed = diff->tissue(Material::Neighbour).removed;
  EXPECT_GT(removed, 0u);
  // Only the premolar: the second molar keeps every voxel whole.
  EXPECT_EQ(before_c.mesial_fill - after_c.mesial_fill, removed);
  EXPECT_EQ(after_c.distal_fill, before_c.distal_fill);
  std::printf("overcut: %.3f mm^3 of the neighbours (%llu voxels fewer)\n",
              double(removed) / DS_FILL_FULL * std::pow(initial.frame.voxel_mm, 3),
              static_cast<unsigned long long>(before_c.voxels[kN] - after_c.voxels[kN]));
}

}  // namespace
}  // namespace dentsim
