// Tests that `dentsim task new` and its help follow eval/task_kinds.h: each kind's and class's defaults, and every row listed.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "eval/crown_targets.h"
#include "eval/task_kinds.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::runDentsim;
using test::TempDir;

// `task new` on the built-in molar at level 5 (it holds caries and a pulp, so every kind is
// possible); the task file written, or null when it failed.
nlohmann::json newTask(const TempDir& dir, const std::string& name, const std::string& flags) {
  const std::string file = dir.file(name + ".json");
  const auto r = runDentsim("task new --tooth builtin:molar --level 5 " + flags + " -o " + file);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return nullptr;
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

TEST(TaskKindsCli, TaskNewGivesEachKindItsRowsDefaults) {
  TempDir dir;
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    const nlohmann::json j = newTask(dir, row.name, std::string("--kind ") + row.name);
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(j["kind"], row.name);
    EXPECT_EQ(j["title"], std::string(row.title) + " (the built-in molar)");
    EXPECT_EQ(j["instructions"], row.instructions);
    EXPECT_EQ(j["tools"]["drill"], row.default_bur);
    EXPECT_EQ(j["target_s"], row.default_target_s);
    if (hasFailureTime(row)) {
      EXPECT_EQ(j["failure_s"], row.default_failure_s);
    } else {
      EXPECT_FALSE(j.contains("failure_s"));
    }
    if (row.builtin_ideal) {
      EXPECT_EQ(j["ideal"], nlohmann::json({{"kind", "builtin_path"}, {"path", row.builtin_ideal}}));
    } else {
      EXPECT_FALSE(j.contains("ideal"));
    }
  }
}

TEST(TaskKindsCli, TaskNewGivesEachClassItsRowsDefaults) {
  TempDir dir;
  for (const CavityClassRow& row : kCavityClassTable) {
    SCOPED_TRACE(row.builtin_ideal);
    const std::string roman = row.black == 1 ? "I" : row.black == 2 ? "II" : row.black == 5 ? "V" : "?";
    const nlohmann::json j = newTask(dir, row.builtin_ideal, "--kind cavity --class " + roman);
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(j["cavity_class"], roman);
    EXPECT_EQ(j["title"], std::string(row.title) + " (the built-in molar)");
    EXPECT_EQ(j["tools"]["drill"], row.bur);
    EXPECT_EQ(j["ideal"]["path"], row.builtin_ideal);
  }
}

// A crown's finish picks its bur and its margin's width from eval/crown_targets.h's rows, on the
// built-in molar (a molar: 4 mm high at least).
TEST(TaskKindsCli, TaskNewGivesEachCrownFinishAndMaterialItsRows) {
  TempDir dir;
  for (const CrownFinishRow& finish : kCrownFinishTable)
    for (const CrownMaterialRow& material : kCrownMaterialTable) {
      SCOPED_TRACE(std::string(material.name) + " on a " + finish.name);
      const nlohmann::json j = newTask(dir, std::string("k_") + finish.name + "_" + material.name,
                                       std::string("--kind crown --finish ") + finish.name + " --material " + material.name);
      ASSERT_FALSE(j.is_null());
      EXPECT_EQ(j["tools"]["drill"], finish.default_bur);
      const CrownBand width = material.*finish.width;
      EXPECT_EQ(j["crown"]["margin_width_mm"], nlohmann::json::array({width.lo, width.hi}));
      EXPECT_EQ(j["crown"]["occlusal_mm"], nlohmann::json::array({material.occlusal.lo, material.occlusal.hi}));
      EXPECT_EQ(j["crown"]["axial_mm"], nlohmann::json::array({material.axial.lo, material.axial.hi}));
      EXPECT_EQ(j["crown"]["min_height_mm"], kCrownMinHeightMolarMm);
    }
}

TEST(TaskKindsCli, HelpAndErrorsListEveryRow) {
  const auto help = runDentsim("task new --help");
  EXPECT_EQ(help.exit_code, 0) << help.output;
  EXPECT_NE(help.output.find(taskKindNameList(", ", " or ")), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--finish"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find(crownFinishNameList(", ", " or ")), std::string::npos) << help.output;
  EXPECT_NE(help.output.find(crownMaterialNameList(", ", " or ")), std::string::npos) << help.output;
  for (const CrownFinishRow& row : kCrownFinishTable) EXPECT_NE(help.output.find(row.default_bur), std::string::npos) << help.output;
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    EXPECT_NE(help.output.find(row.default_bur), std::string::npos) << help.output;
  }
  // Each kind's target in table order, as the help prints numbers.
  std::string targets;
  for (const TaskKindRow& row : kTaskKindTable)
    targets += (targets.empty() ? "" : ", ") + std::to_string(int(row.default_target_s));
  EXPECT_NE(help.output.find("default by kind: " + targets), std::string::npos) << help.output;

  TempDir dir;
  const auto wrong = runDentsim("task new --tooth builtin:molar --level 5 --kind filling -o " + dir.file("f.json"));
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_NE(wrong.output.find("is not one of " + taskKindNameList(", ", ", ")), std::string::npos) << wrong.output;
}

}  // namespace
}  // namespace dentsim
