// Tests of a task's checks beyond its schema: tools from the catalog, the tooth holding the kind's tissue, the axis, the ideal.
#include "eval/task_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

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
