// Bounded, deterministic mutation fuzzing of the task parser: hostile text never crashes it, an accepted task keeps every rule, and every failure is one line.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "eval/task.h"
#include "fuzz_mutations.h"
#include "volume/brick_layout.h"

namespace dentsim {
namespace {

using test::pick;

const std::string kWhere = "fuzz.json";

// Caries and cavity in both versions and a crown, every key present.
const char* const kSeeds[] = {
    R"({"format": "dentsim-task", "version": 2, "name": "caries_removal", "kind": "caries",
        "title": "Remove the caries", "tooth": "builtin:molar", "level": 9,
        "tools": {"drill": "round_bur_010", "mirror": "mirror_size4"},
        "target_s": 300, "failure_s": 900, "force_error_n": 3.0, "insertion_axis": [0, 0, 1], "leeway_mm": 0.2,
        "pulp_exposure_cap": 50, "ideal": {"kind": "volume", "path": "ideal.dvol"},
        "caries": {"healthy_coefficient": 0.5}})",
    R"({"format": "dentsim-task", "version": 2, "name": "class1_cavity", "kind": "cavity",
        "title": "Class I", "tooth": "builtin:molar", "level": 9,
        "tools": {"drill": "fissure_bur_010", "mirror": "mirror_size4"}, "target_s": 600, "force_error_n": 3.0,
        "insertion_axis": [0, 0, 1], "leeway_mm": 0.2, "pulp_exposure_cap": 50,
        "ideal": {"kind": "builtin_path", "path": "class1_cavity"},
        "cavity": {"undercut_coefficient": 1.0, "overcut_coefficient": 1.0, "parallel_coefficient": 0.01,
                   "time_coefficient": 5.0, "force_coefficient": 0.25, "parallel_error_deg": 10.0}})",
    R"({"format": "dentsim-task", "version": 1, "name": "caries_removal", "kind": "caries",
        "title": "Remove the caries", "tooth": "builtin:molar", "level": 9,
        "tools": {"drill": "round_bur_018", "mirror": "mirror_size4"},
        "target_s": 300, "failure_s": 900, "force_error_n": 3.0})",
    R"({"format": "dentsim-task", "version": 1, "name": "class1_cavity", "kind": "cavity",
        "title": "Class I", "tooth": "builtin:molar", "level": 9,
        "tools": {"drill": "fissure_bur_010", "mirror": "mirror_size4"}, "target_s": 600, "force_error_n": 3.0,
        "cavity": {"undercut_coefficient": 1.0, "overcut_coefficient": 1.0, "parallel_coefficient": 0.01,
                   "time_coefficient": 5.0, "parallel_error_deg": 10.0, "insertion_axis": [0, 0, 1],
                   "leeway_mm": 0.2, "ideal": {"kind": "builtin_path", "path": "class1_cavity"}}})",
    R"({"format": "dentsim-task", "version": 2, "name": "crown_preparation", "kind": "crown",
        "title": "Crown", "tooth": "builtin:molar", "level": 9,
        "tools": {"drill": "shoulder_bur_016", "mirror": "mirror_size4"}, "target_s": 900, "force_error_n": 3.0,
        "insertion_axis": [0, 0, 1], "leeway_mm": 0.2, "pulp_exposure_cap": 50,
        "ideal": {"kind": "builtin_path", "path": "crown_prep"},
        "crown": {"finish": "shoulder", "material": "metal-ceramic", "occlusal_mm": [1.5, 2.0], "axial_mm": [1.2, 1.5],
                  "margin_width_mm": [1.0, 1.5], "toc_deg": [10, 20], "toc_near_deg": [4, 30], "min_height_mm": 4,
                  "min_height_width_ratio": 0.4, "margin_above_cej_mm": [-0.5, 1.0], "undercut_tolerance_mm2": 0.5,
                  "undercut_cap": 50}})",
};

// Replacements that aim at the schema rather than at the bytes: numbers out of range or beyond
// the double range, wrong types, repeated and unknown keys.
const char* const kTokens[] = {"1e999", "-1", "0", "NaN", "\"9\"", "[]", "{}", "null", "true", "1e-320",
                               "\"kind\": \"caries\", \"kind\"", "\"extra\": 1, ", "90.0000001", "[0, 0, 0]"};

void mutate(std::string& text, std::mt19937& rng) {
  std::vector<uint8_t> bytes(text.begin(), text.end());
  if (test::mutateBytesGeneric(bytes, rng)) {
    text.assign(bytes.begin(), bytes.end());
    return;
  }
  // A value or a key swapped for a token: after a ':' or a '{' chosen at random.
  std::vector<size_t> marks;
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == ':' || text[i] == '{') marks.push_back(i + 1);
  if (marks.empty()) return;
  const size_t at = marks[pick(rng, marks.size())];
  size_t end = at;
  while (end < text.size() && text[end] != ',' && text[end] != '}') ++end;
  text.replace(at, end - at, kTokens[pick(rng, std::size(kTokens))]);
}

TEST(TaskFuzz, MutatedTasksAreRefusedInOneLineOrKeepEveryRule) {
  std::mt19937 rng(20261122u);
  int accepted = 0, rejected = 0;
  for (int iteration = 0; iteration < 4000; ++iteration) {
    std::string text = kSeeds[pick(rng, std::size(kSeeds))];
    for (size_t k = 0, n = 1 + pick(rng, 3); k < n; ++k) mutate(text, rng);
    const Result<Task> task = parseTask(text, kWhere);
    if (!task.ok()) {
      ++rejected;
      test::assertOneLineRejection(task.message(), kWhere, iteration);
      continue;
    }
    ++accepted;
    ASSERT_TRUE(std::isfinite(task->target_s) && task->target_s > 0) << text;
    ASSERT_TRUE(std::isfinite(task->force_error_n) && task->force_error_n > 0) << text;
    ASSERT_GE(task->level, DS_MIN_LEVEL) << text;
    ASSERT_LE(task->level, DS_MAX_LEVEL) << text;
    ASSERT_FALSE(task->drill_tool.empty()) << text;
    ASSERT_NEAR(norm(task->insertion_axis), 1.0, 1e-12) << text;
    ASSERT_GE(task->leeway_mm, 0.0) << text;
    ASSERT_LE(task->leeway_mm, 1.0) << text;
    ASSERT_GE(task->pulp_exposure_cap, 0.0) << text;
    ASSERT_LE(task->pulp_exposure_cap, 100.0) << text;
    if (task->ideal) {
      ASSERT_FALSE(task->ideal->path.empty()) << text;
    }
    if (task->kind == TaskKind::Caries) {
      ASSERT_GT(task->failure_s, task->target_s) << text;
      ASSERT_TRUE(std::isfinite(task->caries.healthy_coefficient) && task->caries.healthy_coefficient >= 0) << text;
    } else if (task->kind == TaskKind::Crown) {
      const CrownTask& c = task->crown;
      for (auto [lo, hi] : {std::pair{c.occlusal_lo_mm, c.occlusal_hi_mm}, {c.axial_lo_mm, c.axial_hi_mm},
                            {c.margin_lo_mm, c.margin_hi_mm}}) {
        ASSERT_GT(lo, 0.0) << text;
        ASSERT_LT(lo, hi) << text;
        ASSERT_LE(hi, 10.0) << text;
      }
      ASSERT_LE(c.toc_near_lo_deg, c.toc_lo_deg) << text;
      ASSERT_LT(c.toc_lo_deg, c.toc_hi_deg) << text;
      ASSERT_LE(c.toc_hi_deg, c.toc_near_hi_deg) << text;
      ASSERT_GE(c.toc_near_lo_deg, 0.0) << text;
      ASSERT_LE(c.toc_near_hi_deg, 60.0) << text;
      ASSERT_TRUE(c.min_height_mm > 0 && c.min_height_mm <= 20) << text;
      ASSERT_TRUE(c.min_height_width_ratio > 0 && c.min_height_width_ratio <= 10) << text;
      ASSERT_LT(c.margin_above_cej_lo_mm, c.margin_above_cej_hi_mm) << text;
      ASSERT_TRUE(std::isfinite(c.undercut_tolerance_mm2) && c.undercut_tolerance_mm2 >= 0) << text;
      ASSERT_TRUE(c.undercut_cap >= 0 && c.undercut_cap <= 100) << text;
    } else {
      ASSERT_TRUE(task->ideal.has_value()) << text;
      const CavityTask& c = task->cavity;
      ASSERT_GT(c.parallel_error_deg, 0.0) << text;
      ASSERT_LE(c.parallel_error_deg, 90.0) << text;
      for (double coef : {c.undercut_coefficient, c.overcut_coefficient, c.parallel_coefficient, c.time_coefficient,
                          c.force_coefficient})
        ASSERT_TRUE(std::isfinite(coef) && coef >= 0) << text;
    }
  }
  // Both outcomes happen: the mutations neither break every file nor leave them all valid.
  EXPECT_GT(accepted, 50);
  EXPECT_GT(rejected, 1000);
}

}  // namespace
}  // namespace dentsim
