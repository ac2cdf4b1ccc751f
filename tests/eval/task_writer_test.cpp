// Tests of the one writer of task files: a new task's keys and their order, the ideal's object, and a write that never leaves a file the parser refuses.
#include "eval/task_writer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "test_support.h"

namespace dentsim {
namespace {

// A class II cavity on the built-in molar with every optional key a new task may hold.
Task fullTask() {
  Task t;
  t.name = "c2";
  t.kind = TaskKind::Cavity;
  t.cavity_class = 2;
  t.title = "Prepare a class II cavity (the built-in molar)";
  t.instructions = "Cut it.";
  t.tooth = "builtin:molar";
  t.level = 7;
  t.drill_tool = "fissure_bur_010";
  t.mirror_tool = "mirror_size4";
  t.target_s = 600;
  t.force_error_n = 2.5;
  t.pass_mark = 70.0;
  t.insertion_axis = Vec3{0, 0.6, 0.8};
  t.leeway_mm = 0.1;
  t.ideal = idealBuiltinPath("class2_cavity");
  t.from_ideal.target_s = true;
  t.view = TaskView{"occlusal", 20.0, true};
  return t;
}

std::vector<std::string> keysOf(const nlohmann::ordered_json& j) {
  std::vector<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
  return keys;
}

TEST(TaskWriter, ANewTaskHoldsItsKeysInOrderAndReadsBack) {
  const nlohmann::ordered_json j = newTaskJson(fullTask());
  EXPECT_EQ(keysOf(j), (std::vector<std::string>{"format", "version", "name", "kind", "cavity_class", "title", "instructions",
                                                 "tooth", "level", "tools", "target_s", "force_error_n", "pass_mark",
                                                 "insertion_axis", "leeway_mm", "ideal", "from_ideal", "view"}));
  EXPECT_EQ(j["cavity_class"], "II");
  EXPECT_EQ(j["from_ideal"], nlohmann::ordered_json::array({"target_s"}));
  auto t = parseTask(j.dump(2), "t.json");
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->cavity_class, 2);
  EXPECT_EQ(t->mirror_tool, "mirror_size4");
  EXPECT_EQ(t->level, 7);
  EXPECT_EQ(t->pass_mark, 70.0);
  EXPECT_TRUE(t->view && t->view->fixed);
  EXPECT_TRUE(t->from_ideal.target_s && !t->from_ideal.insertion_axis);
}

TEST(TaskWriter, OnlyWhatIsSetIsWritten) {
  // A caries task on a volume file: its failure time, no class, level, mirror, pass mark, ideal, from_ideal or view.
  Task t;
  t.name = "c";
  t.title = "C";
  t.tooth = "t.dvol";
  t.drill_tool = "round_bur_010";
  t.target_s = 300;
  t.failure_s = 900;
  const nlohmann::ordered_json j = newTaskJson(t);
  EXPECT_EQ(keysOf(j), (std::vector<std::string>{"format", "version", "name", "kind", "title", "instructions", "tooth", "tools",
                                                 "target_s", "failure_s", "force_error_n", "insertion_axis", "leeway_mm"}));
  EXPECT_EQ(keysOf(j["tools"]), std::vector<std::string>{"drill"});
}

// A metal-ceramic crown on a shoulder, every target changed from the table's, so that a key the
// writer dropped would read back as the default and show.
Task crownTask() {
  Task t;
  t.name = "k";
  t.kind = TaskKind::Crown;
  t.title = "Prepare the tooth for a full crown";
  t.instructions = "Prepare it.";
  t.tooth = "builtin:molar";
  t.drill_tool = "shoulder_bur_016";
  t.target_s = 900;
  CrownTask& c = t.crown;
  c.finish = "shoulder";
  c.material = "metal-ceramic";
  c.occlusal_lo_mm = 1.6, c.occlusal_hi_mm = 2.1;
  c.axial_lo_mm = 1.25, c.axial_hi_mm = 1.55;
  c.margin_lo_mm = 1.05, c.margin_hi_mm = 1.45;
  c.toc_lo_deg = 8, c.toc_hi_deg = 18;
  c.toc_near_lo_deg = 3, c.toc_near_hi_deg = 28;
  c.min_height_mm = 3;
  c.min_height_width_ratio = 0.35;
  c.margin_above_cej_lo_mm = -0.5, c.margin_above_cej_hi_mm = 0.75;
  c.undercut_tolerance_mm2 = 0.25;
  c.undercut_cap = 40;
  return t;
}

TEST(TaskWriter, ACrownTaskWritesEveryTargetAndReadsItBack) {
  const Task t = crownTask();
  const nlohmann::ordered_json j = newTaskJson(t);
  EXPECT_EQ(keysOf(j).back(), "crown");
  EXPECT_EQ(keysOf(j["crown"]),
            (std::vector<std::string>{"finish", "material", "occlusal_mm", "axial_mm", "margin_width_mm", "toc_deg",
                                      "toc_near_deg", "min_height_mm", "min_height_width_ratio", "margin_above_cej_mm",
                                      "undercut_tolerance_mm2", "undercut_cap"}));
  EXPECT_EQ(j["crown"]["margin_width_mm"], nlohmann::ordered_json::array({1.05, 1.45}));
  auto back = parseTask(j.dump(2), "t.json");
  ASSERT_TRUE(back.ok()) << back.message();
  const CrownTask &a = t.crown, &b = back->crown;
  EXPECT_EQ(b.finish, a.finish);
  EXPECT_EQ(b.material, a.material);
  for (auto [x, y] : {std::pair{a.occlusal_lo_mm, b.occlusal_lo_mm}, {a.occlusal_hi_mm, b.occlusal_hi_mm},
                      {a.axial_lo_mm, b.axial_lo_mm}, {a.axial_hi_mm, b.axial_hi_mm}, {a.margin_lo_mm, b.margin_lo_mm},
                      {a.margin_hi_mm, b.margin_hi_mm}, {a.toc_lo_deg, b.toc_lo_deg}, {a.toc_hi_deg, b.toc_hi_deg},
                      {a.toc_near_lo_deg, b.toc_near_lo_deg}, {a.toc_near_hi_deg, b.toc_near_hi_deg},
                      {a.min_height_mm, b.min_height_mm}, {a.min_height_width_ratio, b.min_height_width_ratio},
                      {a.margin_above_cej_lo_mm, b.margin_above_cej_lo_mm}, {a.margin_above_cej_hi_mm, b.margin_above_cej_hi_mm},
                      {a.undercut_tolerance_mm2, b.undercut_tolerance_mm2}, {a.undercut_cap, b.undercut_cap}})
    EXPECT_EQ(y, x);
  // Written again, the same text: the round trip loses nothing.
  EXPECT_EQ(newTaskJson(*back).dump(2), j.dump(2));
  // Another kind writes no crown object.
  EXPECT_FALSE(newTaskJson(fullTask()).contains("crown"));
}

TEST(TaskWriter, AnIdealWritesTheFieldsItHas) {
  EXPECT_EQ(idealJson(idealVolumeFile("p.dvol")).dump(), R"({"kind":"volume","path":"p.dvol"})");
  IdealSpec s;
  s.kind = IdealKind::Session;
  s.path = "a.ideal.dses";
  s.final_path = "a.ideal.dvol";
  s.initial_hash = "0123456789abcdef";
  s.final_hash = "fedcba9876543210";
  s.session_hash = "00112233445566ff";
  EXPECT_EQ(keysOf(idealJson(s)),
            (std::vector<std::string>{"kind", "path", "final", "initial_hash", "final_hash", "session_hash"}));
  nlohmann::ordered_json j = newTaskJson(fullTask());
  j["ideal"] = idealJson(s);
  auto t = parseTask(j.dump(), "t.json");
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->ideal->final_hash, s.final_hash);
}

TEST(TaskWriter, WritesOnlyWhatParsesAndEndsTheFileWithANewline) {
  test::TempDir dir;
  const std::string path = dir.file("t.json");
  auto written = writeTaskFile(path, newTaskJson(fullTask()));
  ASSERT_TRUE(written.ok()) << written.message();
  EXPECT_EQ(written->name, "c2");
  const std::vector<uint8_t> bytes = test::readBytes(path);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(bytes.back(), '\n');
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), newTaskJson(fullTask()).dump(2) + "\n");

  // The parser's error, naming the file, and nothing written.
  nlohmann::ordered_json bad = newTaskJson(fullTask());
  bad["kind"] = "filling";
  const std::string other = dir.file("u.json");
  auto refused = writeTaskFile(other, bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.message().rfind(other + ": kind: \"filling\" is not one of", 0), 0u) << refused.message();
  EXPECT_FALSE(std::filesystem::exists(other));
}

}  // namespace
}  // namespace dentsim
