// Tests of a task's checks beyond its schema: tools from the catalog, the tooth holding the kind's tissue, the axis, the ideal.
#include "eval/task_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "sim/builtin_tooth.h"
#include "test_support.h"
#include "volume/tooth_file.h"

namespace dentsim {
namespace {

// A task on the built-in molar at level 5, small enough to build in a moment; it holds enamel,
// dentin, pulp and caries.
Task molarTask(TaskKind kind) {
  Task t;
  t.name = "m";
  t.kind = kind;
  t.tooth = "builtin:molar";
  t.level = 5;
  t.drill_tool = taskKindRow(kind).default_bur;
  t.target_s = 300;
  t.failure_s = taskKindRow(kind).default_failure_s;
  return t;
}

TEST(TaskChecks, ACariesTaskOnTheMolarPasses) {
  const TaskProblems p = checkTask(molarTask(TaskKind::Caries));
  EXPECT_TRUE(p.ok());
  EXPECT_TRUE(p.errors.empty());
}

TEST(TaskChecks, ToolsMustBeABurAndAMirrorOfTheCatalog) {
  Task t = molarTask(TaskKind::Caries);
  t.drill_tool = "mirror_size4";
  t.mirror_tool = "round_bur_010";
  const TaskProblems p = checkTask(t);
  ASSERT_EQ(p.errors.size(), 2u);
  EXPECT_EQ(p.errors[0], "tools.drill: \"mirror_size4\" is not a bur in the tool catalog (assets/tools/tools.json)");
  EXPECT_EQ(p.errors[1], "tools.mirror: \"round_bur_010\" is not a mirror in the tool catalog");
}

TEST(TaskChecks, AToothThatDoesNotLoadIsOneError) {
  Task t = molarTask(TaskKind::Caries);
  t.tooth = "/nonexistent/t.dvol";
  const TaskProblems p = checkTask(t);
  ASSERT_EQ(p.errors.size(), 1u);
  EXPECT_EQ(p.errors[0].rfind("tooth: ", 0), 0u) << p.errors[0];
}

TEST(TaskChecks, TheAxisMustSuitTheKind) {
  Task t = molarTask(TaskKind::Caries);
  t.insertion_axis = Vec3{0, 0, -1};
  const TaskProblems p = checkTask(t);
  ASSERT_EQ(p.errors.size(), 1u);
  EXPECT_EQ(p.errors[0].rfind("insertion_axis: points 180 degrees", 0), 0u) << p.errors[0];
}

TEST(TaskChecks, AnIdealThatCannotBeMadeIsAnError) {
  Task t = molarTask(TaskKind::Cavity);
  t.ideal = idealVolumeFile("/nonexistent/ideal.dvol");
  const TaskProblems p = checkTask(t);
  ASSERT_EQ(p.errors.size(), 1u);
  EXPECT_EQ(p.errors[0].rfind("ideal: ", 0), 0u) << p.errors[0];
}

TEST(TaskChecks, AnIdealThatIsTheToothUncutIsRefused) {
  test::TempDir dir;
  auto molar = builtinMolarTooth(5);
  ASSERT_TRUE(molar.ok()) << molar.message();
  const std::string file = dir.file("m.dvol");
  ASSERT_TRUE(saveTooth(file, *molar).ok());
  Task t = molarTask(TaskKind::Cavity);
  t.tooth = file;
  t.ideal = idealVolumeFile(file);
  const TaskProblems p = checkTask(t);
  ASSERT_EQ(p.errors.size(), 1u);
  EXPECT_EQ(p.errors[0], "ideal: the professional's tooth is the task's tooth uncut");
}

TEST(TaskChecks, AnIdealThatCutsANeighbourIsAWarning) {
  test::TempDir dir;
  auto molar = builtinMolarTooth(5);
  ASSERT_TRUE(molar.ok()) << molar.message();
  // A neighbour block of 2 x 2 x 2 voxels in the grid's empty corner.
  ToothVolume tooth = *molar;
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 2; ++y)
      for (uint32_t x = 0; x < 2; ++x) {
        ASSERT_EQ(voxelFill(tooth.voxels.voxel(x, y, z)), 0u) << "the corner is not empty";
        tooth.voxels.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
      }
  // The professional's tooth: the topmost tissue voxel over the grid's centre cut, and 3 neighbour voxels.
  ToothVolume ideal = tooth;
  const uint32_t c = tooth.voxels.dim() / 2;
  uint32_t top = tooth.voxels.dim() - 1;
  while (top > 0 && voxelFill(tooth.voxels.voxel(c, c, top)) == 0) --top;
  ideal.voxels.setVoxel(c, c, top, 0);
  ideal.voxels.setVoxel(0, 0, 0, 0);
  ideal.voxels.setVoxel(1, 0, 0, 0);
  ideal.voxels.setVoxel(0, 1, 0, 0);
  const std::string tooth_file = dir.file("t.dvol"), ideal_file = dir.file("i.dvol");
  ASSERT_TRUE(saveTooth(tooth_file, tooth).ok());
  ASSERT_TRUE(saveTooth(ideal_file, ideal).ok());
  Task t = molarTask(TaskKind::Cavity);
  t.tooth = tooth_file;
  t.ideal = idealVolumeFile(ideal_file);
  const TaskProblems p = checkTask(t);
  EXPECT_TRUE(p.ok());
  // Three whole voxels of the molar's grid.
  const double v = tooth.frame.voxel_mm;
  char mm3[32];
  std::snprintf(mm3, sizeof mm3, "%.3f mm^3", 3 * v * v * v);
  const std::string expected = std::string("ideal: the professional cut ") + mm3 + " of an adjacent tooth";
  const bool found = std::any_of(p.warnings.begin(), p.warnings.end(),
                                 [&](const std::string& w) { return w.rfind(expected, 0) == 0; });
  EXPECT_TRUE(found) << expected;
  // The same ideal without the neighbour cut warns of none.
  ToothVolume clean = ideal;
  for (auto [x, y] : {std::pair{0u, 0u}, {1u, 0u}, {0u, 1u}}) clean.voxels.setVoxel(x, y, 0, makeVoxel(Material::Neighbour));
  ASSERT_TRUE(saveTooth(ideal_file, clean).ok());
  for (const std::string& w : checkTask(t).warnings) EXPECT_EQ(w.find("adjacent tooth"), std::string::npos) << w;
}

// The drill's warnings about a crown's bur, "tools.drill: ..." (its catalog error is not a warning).
std::vector<std::string> drillWarnings(const Task& t) {
  std::vector<std::string> out;
  for (const std::string& w : checkTask(t).warnings)
    if (w.rfind("tools.drill: ", 0) == 0) out.push_back(w);
  return out;
}

TEST(TaskChecks, ACrownsBurMustCutItsFinishLineOrItIsAWarning) {
  // The kind's own bur on its own finish: nothing said of the bur (until the catalog holds
  // chamfer_bur_016, the catalog's error says it is unknown, and that is all).
  Task t = molarTask(TaskKind::Crown);
  ASSERT_EQ(t.crown.finish, "chamfer");
  EXPECT_TRUE(drillWarnings(t).empty());
  // A round bur cuts no finish line: a warning, not an error, naming the chamfer's burs.
  t.drill_tool = "round_bur_010";
  const TaskProblems round = checkTask(t);
  EXPECT_TRUE(round.ok()) << (round.errors.empty() ? "" : round.errors[0]);
  ASSERT_EQ(drillWarnings(t).size(), 1u);
  const std::string w = drillWarnings(t)[0];
  EXPECT_EQ(w.rfind("tools.drill: \"round_bur_010\" cuts no crown finish line (chamfer or shoulder); a chamfer is cut with ", 0),
            0u) << w;
  EXPECT_NE(w.find("chamfer_bur_016"), std::string::npos) << w;
  EXPECT_EQ(w.find("shoulder_bur"), std::string::npos) << w;
  // A chamfer's bur on a shoulder, and the other way round.
  t.crown.finish = "shoulder";
  t.drill_tool = "chamfer_bur_016";
  ASSERT_EQ(drillWarnings(t).size(), 1u);
  EXPECT_EQ(drillWarnings(t)[0].rfind(
                "tools.drill: \"chamfer_bur_016\" cuts a chamfer, but crown.finish is shoulder; a shoulder is cut with ", 0),
            0u) << drillWarnings(t)[0];
  EXPECT_NE(drillWarnings(t)[0].find("shoulder_bur_016"), std::string::npos) << drillWarnings(t)[0];
  t.crown.finish = "chamfer";
  t.drill_tool = "shoulder_bur_016";
  ASSERT_EQ(drillWarnings(t).size(), 1u);
  EXPECT_EQ(drillWarnings(t)[0].rfind("tools.drill: \"shoulder_bur_016\" cuts a shoulder, but crown.finish is chamfer", 0), 0u)
      << drillWarnings(t)[0];
  // Only a crown's bur is held to a finish line.
  Task cavity = molarTask(TaskKind::Cavity);
  cavity.drill_tool = "round_bur_010";
  EXPECT_TRUE(drillWarnings(cavity).empty());
}

TEST(TaskChecks, TheRequiredTissueIsTheRowsAndOnlyCountsWhenMissing) {
  MaterialTotals none;
  MaterialTotals all;
  for (uint64_t& n : all.voxels) n = 1;
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    EXPECT_EQ(lacksRequiredTissue(row, none), row.required_tissue != Material::Empty);
    EXPECT_FALSE(lacksRequiredTissue(row, all));
  }
  MaterialTotals no_caries = all;
  no_caries.voxels[size_t(Material::Caries)] = 0;
  EXPECT_TRUE(lacksRequiredTissue(taskKindRow(TaskKind::Caries), no_caries));
  EXPECT_FALSE(lacksRequiredTissue(taskKindRow(TaskKind::Access), no_caries));
}

}  // namespace
}  // namespace dentsim
