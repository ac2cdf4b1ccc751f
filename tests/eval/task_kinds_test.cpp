// Tests of the task-kind table against its users: each row's defaults make a task the parser reads back as that kind, its bur and built-in paths exist, its pulp rule is the parser's and the class report's.
#include "eval/task_kinds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "eval/class_report.h"
#include "eval/crown_targets.h"
#include "eval/task_axis.h"
#include "eval/task_writer.h"
#include "model/tool_generator.h"
#include "sim/course_paths.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

// A task of the row's kind with every default `task new` takes from the row, on the built-in molar.
Task taskOfRow(const TaskKindRow& row) {
  Task t;
  t.name = std::string("a_") + row.name;
  t.kind = row.kind;
  t.title = row.title;
  t.instructions = row.instructions;
  t.tooth = "builtin:molar";
  t.drill_tool = row.default_bur;
  t.target_s = row.default_target_s;
  t.failure_s = row.default_failure_s;
  if (row.builtin_ideal) t.ideal = idealBuiltinPath(row.builtin_ideal);
  return t;
}

// A bur: any cutting head of the catalog, all but the handpiece and the mirror.
bool isCatalogBur(const std::string& name) {
  return std::any_of(toolCatalog().begin(), toolCatalog().end(), [&](const ToolSpec& s) {
    return name == s.name && s.kind != ToolKind::Handpiece && s.kind != ToolKind::Mirror;
  });
}

TEST(TaskKinds, EveryRowsDefaultsParseAsThatKind) {
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    const std::string text = newTaskJson(taskOfRow(row)).dump(2);
    auto parsed = parseTask(text, "t.json");
    ASSERT_TRUE(parsed.ok()) << parsed.message() << "\n" << text;
    EXPECT_EQ(parsed->kind, row.kind);
    EXPECT_STREQ(taskKindName(parsed->kind), row.name);
    EXPECT_EQ(parsed->drill_tool, row.default_bur);
    EXPECT_EQ(parsed->target_s, row.default_target_s);
    EXPECT_EQ(parsed->failure_s, row.default_failure_s);
    EXPECT_EQ(parsed->ideal.has_value(), row.builtin_ideal != nullptr);
    EXPECT_EQ(findTaskKind(row.name), &row);
  }
  EXPECT_EQ(findTaskKind("filling"), nullptr);
}

TEST(TaskKinds, ARequiredIdealOrFailureTimeIsRequiredByTheParser) {
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    Task t = taskOfRow(row);
    t.ideal.reset();
    auto no_ideal = parseTask(newTaskJson(t).dump(), "t.json");
    EXPECT_EQ(no_ideal.ok(), !row.ideal_required) << (no_ideal.ok() ? "" : no_ideal.message());
    if (row.ideal_required) {
      EXPECT_EQ(no_ideal.message(), "t.json: ideal: missing");
    }
    // A failure time on a kind without one is a mistake, and one missing from a kind with one.
    nlohmann::ordered_json j = newTaskJson(taskOfRow(row));
    if (hasFailureTime(row)) {
      j.erase("failure_s");
      EXPECT_EQ(parseTask(j.dump(), "t.json").message(), "t.json: failure_s: missing");
    } else {
      j["failure_s"] = 2 * row.default_target_s;
      EXPECT_EQ(parseTask(j.dump(), "t.json").message().rfind("t.json: failure_s: only for kind ", 0), 0u);
    }
  }
}

TEST(TaskKinds, AKindIsReadOnlyFromItsFirstVersion) {
  for (const TaskKindRow& row : kTaskKindTable) {
    if (row.since_version == 1) continue;
    // Only the keys every version has, so that the kind is the first thing wrong.
    const nlohmann::ordered_json j = {{"format", "dentsim-task"}, {"version", row.since_version - 1}, {"name", "a"},
                                      {"kind", row.name}, {"tooth", "builtin:molar"}, {"tools", {{"drill", row.default_bur}}},
                                      {"target_s", row.default_target_s}, {"force_error_n", 3}};
    EXPECT_EQ(parseTask(j.dump(), "t.json").message(),
              "t.json: kind: \"" + std::string(row.name) + "\" needs version " + std::to_string(row.since_version));
  }
}

TEST(TaskKinds, ThePulpRuleDecidesTheExposureCapAndTheClassReportsFlag) {
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    nlohmann::ordered_json j = newTaskJson(taskOfRow(row));
    j["pulp_exposure_cap"] = 30;
    EXPECT_EQ(parseTask(j.dump(), "t.json").ok(), row.pulp == PulpRule::ExposureCaps);
    j.erase("pulp_exposure_cap");
    j["access"] = {{"unopened_cap", 30}};
    EXPECT_EQ(parseTask(j.dump(), "t.json").ok(), row.pulp == PulpRule::MustOpen);

    ClassAttempt a;
    a.student = "ann";
    a.task = "t";
    a.task_kind = row.name;
    a.score = 90;
    a.pulp_exposed = true;
    const ClassReport r = buildClassReport({a}, ClassReportOptions{});
    EXPECT_EQ(r.flags.size(), row.pulp == PulpRule::ExposureCaps ? 1u : 0u);
  }
}

TEST(TaskKinds, DefaultsNameToolsPathsAndTissuesThatExist) {
  for (const TaskKindRow& row : kTaskKindTable) {
    SCOPED_TRACE(row.name);
    EXPECT_TRUE(isCatalogBur(row.default_bur));
    if (row.builtin_ideal) {
      EXPECT_TRUE(isBuiltinPath(row.builtin_ideal));
    }
    if (row.required_tissue != Material::Empty) {
      EXPECT_NE(findTissue(row.required_tissue), nullptr);
      EXPECT_STRNE(row.without_tissue, "");
      EXPECT_STRNE(row.tissue_hint, "");
    }
  }
  for (const CavityClassRow& row : kCavityClassTable) {
    SCOPED_TRACE(row.builtin_ideal);
    EXPECT_TRUE(isCatalogBur(row.bur));
    EXPECT_TRUE(isBuiltinPath(row.builtin_ideal));
    // The class a path cuts is read from the same rows backward.
    EXPECT_EQ(builtinPathClass(row.builtin_ideal), row.black);
    EXPECT_EQ(findCavityClass(row.black), &row);
  }
  EXPECT_EQ(findCavityClass(4), nullptr);
  // A crown's bur for each finish line is a bur its own finish names.
  for (const CrownFinishRow& row : kCrownFinishTable) {
    SCOPED_TRACE(row.name);
    EXPECT_TRUE(isCatalogBur(row.default_bur));
    EXPECT_EQ(crownFinishOfBur(row.default_bur), &row);
  }
}

TEST(TaskKinds, TheNameListHoldsEveryRowInOrder) {
  const std::string list = taskKindNameList(", ", " or ");
  size_t at = 0;
  for (const TaskKindRow& row : kTaskKindTable) {
    const size_t found = list.find(row.name, at);
    ASSERT_NE(found, std::string::npos) << list;
    at = found + 1;
  }
  // n names: n - 2 separators between them and the last separator once.
  const std::string marked = taskKindNameList("/", "|");
  EXPECT_EQ(std::count(marked.begin(), marked.end(), '/'), long(kTaskKindCount) - 2);
  EXPECT_EQ(std::count(marked.begin(), marked.end(), '|'), 1);
}

}  // namespace
}  // namespace dentsim
