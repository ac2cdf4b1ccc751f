// Tests of task files: the checked-in tasks parse, version 1 files still do, defaults apply, and each kind of mistake gives its one-line error.
#include "eval/task.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <utility>

#include "eval/crown_targets.h"
#include "eval/task_writer.h"
#include "test_support.h"

namespace dentsim {
namespace {

const std::string kWhere = "t.json";

// The source tree's assets/tasks, found from this file's path.
std::string assetTask(const std::string& file) {
  return (std::filesystem::path(DENTSIM_SOURCE_DIR) / "assets" / "tasks" / file).string();
}

// A caries task with `extra` members appended (JSON text after a comma), or `replace` instead of the body.
std::string cariesText(const std::string& extra = "") {
  return std::string(R"({"format": "dentsim-task", "version": 1, "name": "c", "kind": "caries", "tooth": "builtin:molar",)"
                     R"( "tools": {"drill": "round_bur_010"}, "target_s": 300, "failure_s": 900, "force_error_n": 3)") +
         (extra.empty() ? "" : ", " + extra) + "}";
}
std::string cavityText(const std::string& cavity_extra = "", const std::string& extra = "") {
  return std::string(R"({"format": "dentsim-task", "version": 1, "name": "v", "kind": "cavity", "tooth": "builtin:molar",)"
                     R"( "tools": {"drill": "fissure_bur_010"}, "target_s": 600, "force_error_n": 3,)"
                     R"( "cavity": {"ideal": {"kind": "volume", "path": "ideal.dvol"})") +
         (cavity_extra.empty() ? "" : ", " + cavity_extra) + "}" + (extra.empty() ? "" : ", " + extra) + "}";
}

std::string errorOf(const std::string& text) {
  auto t = parseTask(text, kWhere);
  EXPECT_FALSE(t.ok()) << text;
  return t.ok() ? std::string() : t.message();
}

TEST(Task, CheckedInTasksParse) {
  auto caries = loadTask(assetTask("caries_removal.json"));
  ASSERT_TRUE(caries.ok()) << caries.message();
  EXPECT_EQ(caries->name, "caries_removal");
  EXPECT_EQ(caries->kind, TaskKind::Caries);
  EXPECT_EQ(caries->tooth, "builtin:molar");
  EXPECT_GT(caries->failure_s, caries->target_s);
  EXPECT_EQ(caries->mirror_tool, "mirror_size4");

  auto cavity = loadTask(assetTask("class1_cavity.json"));
  ASSERT_TRUE(cavity.ok()) << cavity.message();
  EXPECT_EQ(cavity->name, "class1_cavity");
  EXPECT_EQ(cavity->kind, TaskKind::Cavity);
  ASSERT_TRUE(cavity->ideal.has_value());
  EXPECT_EQ(cavity->ideal->kind, IdealKind::BuiltinPath);
  EXPECT_EQ(cavity->leeway_mm, 0.2);
  EXPECT_EQ(cavity->insertion_axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(cavity->pulp_exposure_cap, 50.0);
  EXPECT_EQ(cavity->cavity.force_coefficient, 0.5);
  EXPECT_FALSE(caries->ideal.has_value());
  EXPECT_EQ(caries->caries.healthy_coefficient, 0.5);
}

TEST(Task, DefaultsApplyToOmittedKeys) {
  auto t = parseTask(cavityText(R"("insertion_axis": [0, 0, 2])"), kWhere);
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->title, "v");          // the name stands in
  EXPECT_EQ(t->level, 9);
  EXPECT_EQ(t->mirror_tool, "");
  EXPECT_EQ(t->failure_s, 0.0);
  EXPECT_EQ(t->cavity.undercut_coefficient, 1.0);
  EXPECT_EQ(t->cavity.overcut_coefficient, 1.0);
  EXPECT_EQ(t->cavity.parallel_coefficient, 0.01);
  EXPECT_EQ(t->cavity.time_coefficient, 5.0);
  EXPECT_EQ(t->cavity.parallel_error_deg, 10.0);
  EXPECT_EQ(t->insertion_axis, (Vec3{0, 0, 1}));  // normalized; version 1 keeps it in "cavity"
  ASSERT_TRUE(t->ideal.has_value());
  EXPECT_EQ(t->ideal->kind, IdealKind::Volume);
  EXPECT_EQ(t->ideal->path, "ideal.dvol");
  EXPECT_EQ(t->pulp_exposure_cap, 50.0);
  EXPECT_EQ(t->cavity.force_coefficient, 0.5);
}

// Version 2: the zone's keys at the top for both kinds; a caries task may name an ideal.
std::string v2Text(const std::string& kind_part, const std::string& extra = "") {
  return std::string(R"({"format": "dentsim-task", "version": 2, "name": "n", "tooth": "builtin:molar",)"
                     R"( "tools": {"drill": "round_bur_010"}, "target_s": 300, "force_error_n": 3, )") +
         kind_part + (extra.empty() ? "" : ", " + extra) + "}";
}
const std::string kV2Caries = R"("kind": "caries", "failure_s": 900)";
const std::string kV2Cavity = R"("kind": "cavity", "ideal": {"kind": "volume", "path": "p.dvol"})";

TEST(Task, VersionTwoReadsTheZoneForBothKinds) {
  auto caries = parseTask(v2Text(kV2Caries, R"("insertion_axis": [0, -3, 0], "leeway_mm": 0.1, "pulp_exposure_cap": 30,)"
                                            R"( "ideal": {"kind": "session", "path": "prof.dses"},)"
                                            R"( "caries": {"healthy_coefficient": 2})"),
                          kWhere);
  ASSERT_TRUE(caries.ok()) << caries.message();
  EXPECT_EQ(caries->insertion_axis, (Vec3{0, -1, 0}));
  EXPECT_EQ(caries->leeway_mm, 0.1);
  EXPECT_EQ(caries->pulp_exposure_cap, 30.0);
  ASSERT_TRUE(caries->ideal.has_value());
  EXPECT_EQ(caries->ideal->kind, IdealKind::Session);
  EXPECT_EQ(caries->caries.healthy_coefficient, 2.0);

  auto cavity = parseTask(v2Text(kV2Cavity, R"("cavity": {"force_coefficient": 1})"), kWhere);
  ASSERT_TRUE(cavity.ok()) << cavity.message();
  EXPECT_EQ(cavity->cavity.force_coefficient, 1.0);
  EXPECT_EQ(cavity->cavity.undercut_coefficient, 1.0);  // the cavity object is optional in version 2
  EXPECT_EQ(cavity->ideal->path, "p.dvol");
}

TEST(Task, PassMarkIsOptionalAndWithinTheHundredPoints) {
  auto without = parseTask(v2Text(kV2Caries), kWhere);
  ASSERT_TRUE(without.ok()) << without.message();
  EXPECT_FALSE(without->pass_mark.has_value());  // none: attempts are only "completed"
  auto with = parseTask(v2Text(kV2Cavity, R"("pass_mark": 62.5)"), kWhere);
  ASSERT_TRUE(with.ok()) << with.message();
  ASSERT_TRUE(with->pass_mark.has_value());
  EXPECT_EQ(*with->pass_mark, 62.5);
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("pass_mark": 100.5)")), "t.json: pass_mark: 100.5 is not in [0, 100]");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("pass_mark": "70")")), "t.json: pass_mark: expected a number, got string");
  EXPECT_EQ(errorOf(cariesText(R"("pass_mark": 70)")).rfind("t.json: pass_mark: unknown key", 0), 0u);
}

TEST(Task, AdjacentTermsAreReadForEveryKindAndChecked) {
  auto plain = parseTask(v2Text(kV2Caries), kWhere);
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_EQ(plain->adjacent.coefficient, 100.0);  // docs/SCORING.md's defaults
  EXPECT_EQ(plain->adjacent.min_points, 25.0);
  EXPECT_EQ(plain->adjacent.noise_voxels, 3.0);
  for (const std::string& kind : {kV2Caries, kV2Cavity}) {
    auto t = parseTask(v2Text(kind, R"("adjacent": {"coefficient": 40, "min_points": 100, "noise_voxels": 0})"), kWhere);
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_EQ(t->adjacent.coefficient, 40.0);
    EXPECT_EQ(t->adjacent.min_points, 100.0);
    EXPECT_EQ(t->adjacent.noise_voxels, 0.0);
  }
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("adjacent": {"min_points": 100.5})")),
            "t.json: adjacent.min_points: 100.5 is not in [0, 100]");
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("adjacent": {"noise_voxels": -1})")),
            "t.json: adjacent.noise_voxels: -1 is not >= 0 and <= 1e9");
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("adjacent": {"coefficent": 1})")).rfind("t.json: adjacent.coefficent: unknown key", 0), 0u);
  // Version 1 does not know it.
  EXPECT_EQ(errorOf(cariesText(R"("adjacent": {})")).rfind("t.json: adjacent: unknown key", 0), 0u);
}

TEST(Task, VersionTwoErrors) {
  EXPECT_EQ(errorOf(v2Text(R"("kind": "cavity")")), "t.json: ideal: missing");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("pulp_exposure_cap": 101)")), "t.json: pulp_exposure_cap: 101 is not in [0, 100]");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("caries": {"healthy_coefficient": -0.5})")),
            "t.json: caries.healthy_coefficient: -0.5 is not >= 0 and <= 1e9");
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("caries": {})")), "t.json: caries: only for kind \"caries\"");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("cavity": {})")), "t.json: cavity: only for kind \"cavity\"");
  // The zone's keys moved out of "cavity"; version 2 does not take them there.
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("cavity": {"leeway_mm": 0.1})")).rfind("t.json: cavity.leeway_mm: unknown key", 0),
            0u);
  // Version 1 does not know the new keys.
  EXPECT_EQ(errorOf(cariesText(R"("pulp_exposure_cap": 50)")).rfind("t.json: pulp_exposure_cap: unknown key", 0), 0u);
}

TEST(Task, ErrorsNameTheFileAndKey) {
  EXPECT_EQ(errorOf("{"), "t.json: invalid JSON: parse error at line 1, column 2: syntax error while parsing object key - "
                          "unexpected end of input; expected string literal");
  EXPECT_EQ(errorOf("[]"), "t.json: (top level): expected an object, got array");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-params", "version": 1})"),
            "t.json: format: \"dentsim-params\" is not \"dentsim-task\"");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task", "version": 3})"),
            "t.json: version: 3 is not supported (this build reads versions 1 to 2)");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task"})"), "t.json: version: missing");
  // Unknown keys, at the top and inside.
  EXPECT_EQ(errorOf(cariesText(R"("colour": 1)")).rfind("t.json: colour: unknown key (known: format, version,", 0), 0u);
  EXPECT_EQ(errorOf(cavityText(R"("leeway": 0.1)")).rfind("t.json: cavity.leeway: unknown key (known:", 0), 0u);
  // Missing and mistyped.
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task", "version": 1, "kind": "caries"})"), "t.json: name: missing");
  EXPECT_EQ(errorOf(cariesText(R"("level": "nine")")), "t.json: level: expected an integer, got string");
  EXPECT_EQ(errorOf(cavityText(R"("time_coefficient": true)")),
            "t.json: cavity.time_coefficient: expected a number, got boolean");
  // Out of range.
  EXPECT_EQ(errorOf(cariesText(R"("level": 20)")), "t.json: level: 20 is not in [3, 13]");
  EXPECT_EQ(errorOf(cavityText(R"("leeway_mm": 5)")), "t.json: cavity.leeway_mm: 5 is not in [0, 1]");
  EXPECT_EQ(errorOf(cavityText(R"("parallel_error_deg": 0)")), "t.json: cavity.parallel_error_deg: 0 is not in (0, 90]");
  EXPECT_EQ(errorOf(cavityText(R"("overcut_coefficient": -1)")),
            "t.json: cavity.overcut_coefficient: -1 is not >= 0 and <= 1e9");
  EXPECT_EQ(errorOf(cavityText(R"("insertion_axis": [0, 0, 0])")),
            "t.json: cavity.insertion_axis: zero vector; the axis needs a direction");
  EXPECT_EQ(errorOf(cavityText(R"("insertion_axis": [0, 1])")),
            "t.json: cavity.insertion_axis: expected an array of 3 numbers");
  // The failure time must come after the target.
  auto early = std::string(R"({"format": "dentsim-task", "version": 1, "name": "c", "kind": "caries", "tooth": "x",)"
                           R"( "tools": {"drill": "round_bur_010"}, "target_s": 300, "failure_s": 200, "force_error_n": 3})");
  EXPECT_EQ(errorOf(early), "t.json: failure_s: 200.0 is not > target_s (300.0)");
  // Keys of the other kind.
  EXPECT_EQ(errorOf(cariesText(R"("cavity": {})")), "t.json: cavity: only for kind \"cavity\"");
  EXPECT_EQ(errorOf(cavityText("", R"("failure_s": 900)")), "t.json: failure_s: only for kind \"caries\"");
  // Choices, names, repeats.
  EXPECT_EQ(errorOf(cavityText(R"("ideal": {"kind": "guess", "path": "a"})")),
            "t.json: cavity.ideal: repeated key");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task", "version": 1, "name": "c", "kind": "filling"})"),
            "t.json: kind: \"filling\" is not one of \"caries\", \"cavity\", \"access\", \"crown\"");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task", "version": 1, "name": "a b"})"),
            "t.json: name: \"a b\" is not a name (1 to 64 letters, digits, '_', '-', '.')");
}

// A version 2 access task with `extra` members appended.
std::string accessText(const std::string& extra = "") {
  return std::string(R"({"format": "dentsim-task", "version": 2, "name": "a", "kind": "access", "tooth": "builtin:molar",)"
                     R"( "tools": {"drill": "round_bur_014"}, "target_s": 900, "force_error_n": 3,)"
                     R"( "ideal": {"kind": "builtin_path", "path": "access_cavity"})") +
         (extra.empty() ? "" : ", " + extra) + "}";
}

TEST(Task, TheCourseTasksParse) {
  for (const char* name : {"class2_cavity", "class5_cavity", "access_cavity"}) {
    auto t = loadTask(assetTask(std::string(name) + ".json"));
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_EQ(t->name, name);
    EXPECT_EQ(t->tooth, "builtin:molar");
    ASSERT_TRUE(t->ideal.has_value());
    EXPECT_EQ(t->ideal->kind, IdealKind::BuiltinPath);
    EXPECT_EQ(t->ideal->path, name);  // each names its own built-in path
    EXPECT_FALSE(t->instructions.empty());
  }
  auto access = loadTask(assetTask("access_cavity.json"));
  ASSERT_TRUE(access.ok());
  EXPECT_EQ(access->kind, TaskKind::Access);
  EXPECT_EQ(access->access.unopened_cap, 40.0);
  EXPECT_STREQ(taskKindName(access->kind), "access");
  // The class V bur comes from buccal, level: within 15 degrees of the surface normal just above the CEJ.
  auto class5 = loadTask(assetTask("class5_cavity.json"));
  ASSERT_TRUE(class5.ok());
  EXPECT_LT(class5->insertion_axis.y, -0.9);
  EXPECT_NEAR(norm(class5->insertion_axis), 1.0, 1e-12);
  // Each cavity says its Black class; nothing shipped leaves a key to a professional's session.
  for (auto [name, black] : {std::pair{"class1_cavity", 1}, {"class1_indirect", 1}, {"class2_cavity", 2}, {"class5_cavity", 5}}) {
    auto t = loadTask(assetTask(std::string(name) + ".json"));
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_EQ(t->cavity_class, black) << name;
    EXPECT_FALSE(t->from_ideal.any()) << name;
  }
}

// from_ideal names the keys set-ideal may set: each at most once, and only those two.
TEST(Task, FromIdealListsTheKeysTheProfessionalSets) {
  auto none = parseTask(v2Text(kV2Caries), kWhere);
  ASSERT_TRUE(none.ok()) << none.message();
  EXPECT_FALSE(none->from_ideal.any());
  auto both = parseTask(v2Text(kV2Cavity, R"("from_ideal": ["target_s", "insertion_axis"])"), kWhere);
  ASSERT_TRUE(both.ok()) << both.message();
  EXPECT_TRUE(both->from_ideal.insertion_axis);
  EXPECT_TRUE(both->from_ideal.target_s);
  auto axis = parseTask(v2Text(kV2Caries, R"("from_ideal": ["insertion_axis"])"), kWhere);
  ASSERT_TRUE(axis.ok()) << axis.message();
  EXPECT_TRUE(axis->from_ideal.insertion_axis);
  EXPECT_FALSE(axis->from_ideal.target_s);
  auto empty = parseTask(v2Text(kV2Caries, R"("from_ideal": [])"), kWhere);
  ASSERT_TRUE(empty.ok()) << empty.message();
  EXPECT_FALSE(empty->from_ideal.any());

  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("from_ideal": ["failure_s"])")),
            "t.json: from_ideal[0]: \"failure_s\" is not one of \"insertion_axis\", \"target_s\"");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("from_ideal": ["target_s", "target_s"])")),
            "t.json: from_ideal[1]: \"target_s\" is listed twice");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("from_ideal": "target_s")")),
            "t.json: from_ideal: expected an array of key names, got string");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("from_ideal": [1])")), "t.json: from_ideal[0]: expected a key name, got number");
  EXPECT_EQ(errorOf(cariesText(R"("from_ideal": [])")).rfind("t.json: from_ideal: unknown key", 0), 0u);  // version 2 only
}

TEST(Task, CavityClassIsBlacksAndOnlyForACavity) {
  auto v = parseTask(v2Text(kV2Cavity, R"("cavity_class": "V")"), kWhere);
  ASSERT_TRUE(v.ok()) << v.message();
  EXPECT_EQ(v->cavity_class, 5);
  auto six = parseTask(v2Text(kV2Cavity, R"("cavity_class": "VI")"), kWhere);
  ASSERT_TRUE(six.ok()) << six.message();
  EXPECT_EQ(six->cavity_class, 6);
  auto none = parseTask(v2Text(kV2Cavity), kWhere);
  ASSERT_TRUE(none.ok()) << none.message();
  EXPECT_EQ(none->cavity_class, 0);
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("cavity_class": "5")")),
            "t.json: cavity_class: \"5\" is not one of \"I\", \"II\", \"III\", \"IV\", \"V\", \"VI\"");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("cavity_class": "I")")), "t.json: cavity_class: only for kind \"cavity\"");
  EXPECT_EQ(errorOf(accessText(R"("cavity_class": "I")")), "t.json: cavity_class: only for kind \"cavity\"");
  EXPECT_STREQ(cavityClassName(2), "II");
  EXPECT_STREQ(cavityClassName(7), "");
  EXPECT_EQ(cavityClassFromName("IV"), 4);
  EXPECT_EQ(cavityClassFromName("iv"), 0);
}

TEST(Task, AccessKeysBelongToTheAccessKind) {
  auto t = parseTask(accessText(R"("access": {"unopened_cap": 25}, "cavity": {"overcut_coefficient": 2})"), kWhere);
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->access.unopened_cap, 25.0);
  EXPECT_EQ(t->cavity.overcut_coefficient, 2.0);  // scored as a cavity, with its coefficients
  auto plain = parseTask(accessText(), kWhere);
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_EQ(plain->access.unopened_cap, 40.0);  // the default
  EXPECT_EQ(errorOf(accessText(R"("access": {"unopened_cap": 120})")), "t.json: access.unopened_cap: 120 is not in [0, 100]");
  EXPECT_EQ(errorOf(accessText(R"("access": {"cap": 10})")).rfind("t.json: access", 0), 0u);
  EXPECT_EQ(errorOf(accessText(R"("pulp_exposure_cap": 50)")).rfind("t.json: pulp_exposure_cap: not for kind \"access\"", 0), 0u);
  EXPECT_EQ(errorOf(accessText(R"("caries": {})")), "t.json: caries: only for kind \"caries\"");
  // An access needs its ideal, as a cavity does.
  const std::string no_ideal =
      R"({"format": "dentsim-task", "version": 2, "name": "a", "kind": "access", "tooth": "builtin:molar",)"
      R"( "tools": {"drill": "round_bur_014"}, "target_s": 900, "force_error_n": 3})";
  EXPECT_EQ(errorOf(no_ideal), "t.json: ideal: missing");
  // The access key on another kind, and the access kind in a version 1 file.
  EXPECT_EQ(errorOf(cariesText().replace(cariesText().find("\"version\": 1"), 12, "\"version\": 2").insert(1, R"("access": {}, )")),
            "t.json: access: only for kind \"access\"");
  EXPECT_EQ(errorOf(R"({"format": "dentsim-task", "version": 1, "name": "a", "kind": "access"})"),
            "t.json: kind: \"access\" needs version 2");
}

// A version 2 crown task, with no ideal, with `extra` members appended.
std::string crownText(const std::string& extra = "") {
  return std::string(R"({"format": "dentsim-task", "version": 2, "name": "k", "kind": "crown", "tooth": "builtin:molar",)"
                     R"( "tools": {"drill": "chamfer_bur_016"}, "target_s": 900, "force_error_n": 3)") +
         (extra.empty() ? "" : ", " + extra) + "}";
}
// The same with a crown object of `members`.
std::string crownObjectText(const std::string& members) { return crownText(R"("crown": {)" + members + "}"); }

// The table's figures, by hand: all-ceramic 1.5-2 / 1-1.5 / 0.8-1.5 either finish; metal-ceramic
// 1.5-2 / 1.2-1.5, a shoulder 1-1.5 and a chamfer 0.5-1; metal 1-1.5 / 0.5-1, a chamfer 0.5-0.8
// and a shoulder 0.8-1.2. What every material shares: TOC 10-20 (near 4-30), 4 mm, 0.4.
TEST(Task, CrownTargetsAreTheTablesByMaterialAndFinish) {
  struct Expected {
    const char *finish, *material;
    double occlusal_lo, occlusal_hi, axial_lo, axial_hi, margin_lo, margin_hi;
  };
  for (const Expected& e : {Expected{"chamfer", "all-ceramic", 1.5, 2.0, 1.0, 1.5, 0.8, 1.5},
                            Expected{"shoulder", "all-ceramic", 1.5, 2.0, 1.0, 1.5, 0.8, 1.5},
                            Expected{"chamfer", "metal-ceramic", 1.5, 2.0, 1.2, 1.5, 0.5, 1.0},
                            Expected{"shoulder", "metal-ceramic", 1.5, 2.0, 1.2, 1.5, 1.0, 1.5},
                            Expected{"chamfer", "metal", 1.0, 1.5, 0.5, 1.0, 0.5, 0.8},
                            Expected{"shoulder", "metal", 1.0, 1.5, 0.5, 1.0, 0.8, 1.2}}) {
    SCOPED_TRACE(std::string(e.material) + " on a " + e.finish);
    auto c = crownTargets(e.finish, e.material);
    ASSERT_TRUE(c.ok()) << c.message();
    EXPECT_EQ(c->finish, e.finish);
    EXPECT_EQ(c->material, e.material);
    EXPECT_EQ(c->occlusal_lo_mm, e.occlusal_lo);
    EXPECT_EQ(c->occlusal_hi_mm, e.occlusal_hi);
    EXPECT_EQ(c->axial_lo_mm, e.axial_lo);
    EXPECT_EQ(c->axial_hi_mm, e.axial_hi);
    EXPECT_EQ(c->margin_lo_mm, e.margin_lo);
    EXPECT_EQ(c->margin_hi_mm, e.margin_hi);
    EXPECT_EQ(c->toc_lo_deg, 10.0);
    EXPECT_EQ(c->toc_hi_deg, 20.0);
    EXPECT_EQ(c->toc_near_lo_deg, 4.0);
    EXPECT_EQ(c->toc_near_hi_deg, 30.0);
    EXPECT_EQ(c->min_height_mm, 4.0);
    EXPECT_EQ(c->min_height_width_ratio, 0.4);
  }
  EXPECT_EQ(kCrownMinHeightOtherMm, 3.0);
  // task.h's defaults are the table's first finish and material, so a Task{} is a valid crown task.
  EXPECT_EQ(crownJson(CrownTask{}), crownJson(*crownTargets("chamfer", "all-ceramic")));
  EXPECT_EQ(crownTargets("bevel", "metal").message(), "finish \"bevel\" is not chamfer or shoulder");
  EXPECT_EQ(crownTargets("chamfer", "zirconia").message(),
            "material \"zirconia\" is not all-ceramic, metal-ceramic or metal");
  // Each finish's burs, by name.
  EXPECT_EQ(crownFinishOfBur("chamfer_bur_016"), findCrownFinish("chamfer"));
  EXPECT_EQ(crownFinishOfBur("shoulder_bur_012"), findCrownFinish("shoulder"));
  EXPECT_EQ(crownFinishOfBur("fissure_bur_010"), nullptr);
}

TEST(Task, ACrownTaskTakesItsBandsFromItsFinishAndMaterial) {
  // No object, no ideal: an all-ceramic crown on a chamfer, measured from the prepared shape alone.
  auto plain = parseTask(crownText(), kWhere);
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_EQ(plain->kind, TaskKind::Crown);
  EXPECT_STREQ(taskKindName(plain->kind), "crown");
  EXPECT_FALSE(plain->ideal.has_value());
  EXPECT_EQ(crownJson(plain->crown), crownJson(*crownTargets("chamfer", "all-ceramic")));
  // An ideal is accepted.
  auto ideal = parseTask(crownText(R"("ideal": {"kind": "builtin_path", "path": "crown_prep"})"), kWhere);
  ASSERT_TRUE(ideal.ok()) << ideal.message();
  EXPECT_EQ(ideal->ideal->path, "crown_prep");
  // Only the finish and the material: that material's bands for that finish.
  auto mc = parseTask(crownObjectText(R"("finish": "shoulder", "material": "metal-ceramic")"), kWhere);
  ASSERT_TRUE(mc.ok()) << mc.message();
  EXPECT_EQ(mc->crown.axial_lo_mm, 1.2);
  EXPECT_EQ(mc->crown.margin_lo_mm, 1.0);
  EXPECT_EQ(mc->crown.margin_hi_mm, 1.5);
  EXPECT_EQ(crownJson(mc->crown), crownJson(*crownTargets("shoulder", "metal-ceramic")));
  // A key given replaces only its own band; the rest stay the material's.
  auto own = parseTask(crownObjectText(R"("material": "metal", "axial_mm": [0.6, 0.9], "margin_above_cej_mm": [-0.5, 0.5],)"
                                       R"( "min_height_mm": 3, "undercut_cap": 0, "undercut_tolerance_mm2": 0, "toc_deg": [6, 12])"),
                         kWhere);
  ASSERT_TRUE(own.ok()) << own.message();
  EXPECT_EQ(own->crown.finish, "chamfer");
  EXPECT_EQ(own->crown.axial_lo_mm, 0.6);
  EXPECT_EQ(own->crown.axial_hi_mm, 0.9);
  EXPECT_EQ(own->crown.occlusal_lo_mm, 1.0);  // metal's
  EXPECT_EQ(own->crown.margin_hi_mm, 0.8);    // metal's chamfer
  EXPECT_EQ(own->crown.margin_above_cej_lo_mm, -0.5);  // subgingival
  EXPECT_EQ(own->crown.min_height_mm, 3.0);
  EXPECT_EQ(own->crown.undercut_cap, 0.0);
  EXPECT_EQ(own->crown.undercut_tolerance_mm2, 0.0);
  EXPECT_EQ(own->crown.toc_lo_deg, 6.0);
}

TEST(Task, EachCrownKeyRefusesWhatIsOutOfRange) {
  for (auto [members, error] : std::initializer_list<std::pair<const char*, const char*>>{
           {R"("finish": "bevel")", "crown.finish: \"bevel\" is not one of \"chamfer\", \"shoulder\""},
           {R"("material": "gold")", "crown.material: \"gold\" is not one of \"all-ceramic\", \"metal-ceramic\", \"metal\""},
           {R"("occlusal_mm": [2, 1.5])", "crown.occlusal_mm: lo 2 is not < hi 1.5"},
           {R"("occlusal_mm": [1.5, 1.5])", "crown.occlusal_mm: lo 1.5 is not < hi 1.5"},
           {R"("occlusal_mm": [0, 1.5])", "crown.occlusal_mm[0]: 0 is not > 0 and <= 10"},
           {R"("occlusal_mm": 1.5)", "crown.occlusal_mm: expected [lo, hi], an array of 2 numbers"},
           {R"("occlusal_mm": [1, 1.5, 2])", "crown.occlusal_mm: expected [lo, hi], an array of 2 numbers"},
           {R"("axial_mm": [1, "2"])", "crown.axial_mm[1]: expected a number, got string"},
           {R"("axial_mm": [1, 15])", "crown.axial_mm[1]: 15 is not > 0 and <= 10"},
           {R"("margin_width_mm": [-0.8, 1.5])", "crown.margin_width_mm[0]: -0.8 is not > 0 and <= 10"},
           {R"("margin_width_mm": [1.5, 0.8])", "crown.margin_width_mm: lo 1.5 is not < hi 0.8"},
           {R"("toc_deg": [10, 61])", "crown.toc_deg[1]: 61 is not in [0, 60]"},
           {R"("toc_deg": [20, 10])", "crown.toc_deg: lo 20 is not < hi 10"},
           {R"("toc_deg": [2, 20])", "crown.toc_deg: [2.0, 20.0] is not within toc_near_deg [4.0, 30.0] (give toc_near_deg too)"},
           {R"("toc_near_deg": [-1, 30])", "crown.toc_near_deg[0]: -1 is not in [0, 60]"},
           {R"("toc_near_deg": [12, 30])", "crown.toc_near_deg: [12.0, 30.0] does not hold toc_deg [10.0, 20.0]"},
           {R"("min_height_mm": 0)", "crown.min_height_mm: 0 is not > 0 and <= 20"},
           {R"("min_height_width_ratio": -0.4)", "crown.min_height_width_ratio: -0.4 is not > 0 and <= 10"},
           {R"("margin_above_cej_mm": [1, -1])", "crown.margin_above_cej_mm: lo 1 is not < hi -1"},
           {R"("margin_above_cej_mm": [-11, 1])", "crown.margin_above_cej_mm[0]: -11 is not in [-10, 10]"},
           {R"("undercut_tolerance_mm2": -0.1)", "crown.undercut_tolerance_mm2: -0.1 is not >= 0 and <= 1e9"},
           {R"("undercut_cap": 101)", "crown.undercut_cap: 101 is not in [0, 100]"},
           {R"("taper": 12)", "crown.taper: unknown key (known: finish, material, occlusal_mm, axial_mm, margin_width_mm, "
                              "toc_deg, toc_near_deg, min_height_mm, min_height_width_ratio, margin_above_cej_mm, "
                              "undercut_tolerance_mm2, undercut_cap)"},
       }) {
    EXPECT_EQ(errorOf(crownObjectText(members)), std::string("t.json: ") + error);
  }
  EXPECT_EQ(errorOf(crownText(R"("crown": [1])")), "t.json: crown: expected an object, got array");
}

TEST(Task, CrownKeysBelongToTheCrownKind) {
  EXPECT_EQ(errorOf(v2Text(kV2Cavity, R"("crown": {"finish": "chamfer"})")), "t.json: crown: only for kind \"crown\"");
  EXPECT_EQ(errorOf(v2Text(kV2Caries, R"("crown": {})")), "t.json: crown: only for kind \"crown\"");
  EXPECT_EQ(errorOf(crownText(R"("cavity_class": "I")")), "t.json: cavity_class: only for kind \"cavity\"");
  EXPECT_EQ(errorOf(crownText(R"("cavity": {"overcut_coefficient": 2})")), "t.json: cavity: only for kind \"cavity\"");
  EXPECT_EQ(errorOf(crownText(R"("access": {"unopened_cap": 25})")), "t.json: access: only for kind \"access\"");
  EXPECT_EQ(errorOf(crownText(R"("failure_s": 1800)")), "t.json: failure_s: only for kind \"caries\"");
  std::string v1 = crownText();
  v1.replace(v1.find("\"version\": 2"), 12, "\"version\": 1");
  EXPECT_EQ(errorOf(v1), "t.json: kind: \"crown\" needs version 2");
}

TEST(Task, IdealKindMustBeKnown) {
  const std::string text =
      R"({"format": "dentsim-task", "version": 1, "name": "v", "kind": "cavity", "tooth": "builtin:molar",)"
      R"( "tools": {"drill": "fissure_bur_010"}, "target_s": 600, "force_error_n": 3,)"
      R"( "cavity": {"ideal": {"kind": "guess", "path": "a"}}})";
  EXPECT_EQ(errorOf(text), "t.json: cavity.ideal.kind: \"guess\" is not one of \"builtin_path\", \"volume\", \"session\"");
}

TEST(Task, EveryErrorIsOneLine) {
  for (const std::string& text : {std::string("{\"a\":\n"), cariesText("\"x\\u0001\": 1"), std::string("\xff\xfe")}) {
    const std::string e = errorOf(text);
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("t.json: ", 0), 0u) << e;
  }
}

TEST(Task, MissingFileNamesThePath) {
  test::TempDir dir;
  auto t = loadTask(dir.file("none.json"));
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find(dir.file("none.json")), std::string::npos) << t.message();
}

}  // namespace
TEST(Task, InstructionsViewAndIdealIdentityAreRead) {
  const std::string text =
      R"({"format": "dentsim-task", "version": 2, "name": "iv", "kind": "cavity", "tooth": "builtin:molar",)"
      R"( "title": "T", "instructions": "Cut it as seen in the mirror.",)"
      R"( "view": {"camera": "lingual", "elevation_deg": -10, "fixed": true},)"
      R"( "tools": {"drill": "fissure_bur_010"}, "target_s": 600, "force_error_n": 3,)"
      R"( "ideal": {"kind": "session", "path": "p.dses", "initial_hash": "0123456789abcdef", "final_hash": "fedcba9876543210",)"
      R"( "session_hash": "00000000000000ff"}})";
  auto task = parseTask(text, kWhere);
  ASSERT_TRUE(task.ok()) << task.message();
  EXPECT_EQ(task->instructions, "Cut it as seen in the mirror.");
  ASSERT_TRUE(task->view.has_value());
  EXPECT_EQ(task->view->camera, "lingual");
  EXPECT_EQ(task->view->elevation_deg, -10.0);
  EXPECT_TRUE(task->view->fixed);
  ASSERT_TRUE(task->ideal.has_value());
  EXPECT_EQ(task->ideal->initial_hash, "0123456789abcdef");
  EXPECT_EQ(task->ideal->final_hash, "fedcba9876543210");
  EXPECT_EQ(task->ideal->session_hash, "00000000000000ff");

  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = text;
    s.replace(s.find(from), from.size(), to);
    return errorOf(s);
  };
  EXPECT_EQ(with(R"("camera": "lingual")", R"("camera": "left")"),
            "t.json: view.camera: \"left\" is not one of \"occlusal\", \"buccal\", \"lingual\", \"mesial\", \"distal\"");
  EXPECT_EQ(with(R"("elevation_deg": -10)", R"("elevation_deg": 95)"), "t.json: view.elevation_deg: 95 is not in [-89, 89]");
  EXPECT_EQ(with(R"("fixed": true)", R"("fixed": 1)"), "t.json: view.fixed: expected true or false, got number");
  EXPECT_EQ(with(R"("initial_hash": "0123456789abcdef")", R"("initial_hash": "0123")"),
            "t.json: ideal.initial_hash: \"0123\" is not a hash (16 lower-case hex digits)");
}

}  // namespace dentsim
