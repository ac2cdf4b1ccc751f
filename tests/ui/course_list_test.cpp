// Tests of src/ui/course_list.cpp: the pickers' lists from the built-in assets and a course folder made in a temporary directory.
#include "ui/course_list.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/dvol_file.h"
#include "test_support.h"

namespace dentsim::ui {
namespace {

// A version 2 cavity task with a title and instructions (the keys docs/SCORING.md requires).
std::string taskJson(const std::string& name, const std::string& title, const std::string& instructions) {
  return R"({"format":"dentsim-task","version":2,"name":")" + name + R"(","kind":"cavity","title":")" + title +
         R"(","instructions":")" + instructions +
         R"(","tooth":"builtin:molar","level":7,"tools":{"drill":"fissure_bur_010","mirror":"mirror_size4"},)"
         R"("target_s":600,"force_error_n":3.0,"insertion_axis":[0,0,1],"leeway_mm":0.2,"pulp_exposure_cap":50,)"
         R"("ideal":{"kind":"builtin_path","path":"class1_cavity"}})";
}

const TaskChoice* findTask(const CourseList& list, const std::string& label) {
  auto it = std::find_if(list.tasks.begin(), list.tasks.end(), [&](const TaskChoice& t) { return t.label == label; });
  return it == list.tasks.end() ? nullptr : &*it;
}

TEST(CourseList, WithoutAFolderOnlyTheBuiltInTeethAndTasks) {
  const CourseList list = listCourse("");
  // The molar at each level the panel offers, 7 to 10.
  ASSERT_EQ(list.teeth.size(), size_t(kMaxLevel - kMinLevel + 1));
  EXPECT_EQ(list.teeth.front().label, "built-in molar, level 7");
  EXPECT_EQ(list.teeth.front().level, 7);
  EXPECT_TRUE(list.teeth.front().path.empty());
  EXPECT_EQ(list.teeth.back().level, 10);
  // Every embedded task, by the name the simulator starts it by, loaded with its title.
  for (const char* name : {"caries_removal", "class1_cavity", "class1_indirect"}) {
    const TaskChoice* t = findTask(list, name);
    ASSERT_NE(t, nullptr) << name;
    EXPECT_EQ(t->source, name);
    EXPECT_TRUE(t->builtin);
    EXPECT_TRUE(t->error.empty()) << t->error;
    EXPECT_FALSE(t->title.empty()) << name;
  }
  // The indirect-vision task tells the student to work in the mirror.
  EXPECT_NE(findTask(list, "class1_indirect")->instructions.find("mirror"), std::string::npos);
  EXPECT_TRUE(list.error.empty());
}

TEST(CourseList, AFoldersTeethAndTasksWithTitlesInstructionsAndErrors) {
  test::TempDir dir;
  std::ofstream(dir.file("b_molar.dvol")) << "not read by the list";
  std::ofstream(dir.file("a_premolar.dvol")) << "not read by the list";
  std::ofstream(dir.file("notes.txt")) << "neither a tooth nor a task";
  std::filesystem::create_directory(dir.file("sub.dvol"));  // a folder, not a tooth
  std::ofstream(dir.file("occlusal.json")) << taskJson("occlusal", "An occlusal cavity", "Cut along the fissure.");
  std::ofstream(dir.file("broken.json")) << R"({"format":"dentsim-task","version":2,"name":)";

  const CourseList list = listCourse(dir.path().string());
  EXPECT_TRUE(list.error.empty()) << list.error;
  // The built-in teeth first, then the folder's by name.
  const size_t builtin = size_t(kMaxLevel - kMinLevel + 1);
  ASSERT_EQ(list.teeth.size(), builtin + 2);
  EXPECT_EQ(list.teeth[builtin].label, "a_premolar.dvol");
  EXPECT_EQ(list.teeth[builtin].path, dir.file("a_premolar.dvol"));
  EXPECT_EQ(list.teeth[builtin].level, 0);
  EXPECT_EQ(list.teeth[builtin + 1].label, "b_molar.dvol");

  // The tasks: the good one with what its file says, the broken one with why it does not load.
  const TaskChoice* good = findTask(list, "occlusal.json");
  ASSERT_NE(good, nullptr);
  EXPECT_EQ(good->source, dir.file("occlusal.json"));
  EXPECT_FALSE(good->builtin);
  EXPECT_EQ(good->title, "An occlusal cavity");
  EXPECT_EQ(good->instructions, "Cut along the fissure.");
  EXPECT_TRUE(good->error.empty()) << good->error;
  const TaskChoice* broken = findTask(list, "broken.json");
  ASSERT_NE(broken, nullptr);
  EXPECT_FALSE(broken->error.empty());
  EXPECT_NE(broken->error.find("broken.json"), std::string::npos) << "the error names the file: " << broken->error;
  EXPECT_TRUE(broken->title.empty());
  // The folder's files come first, sorted by name, then the built-in tasks.
  ASSERT_GT(list.tasks.size(), 2u);
  EXPECT_EQ(list.tasks[0].label, "broken.json");
  EXPECT_EQ(list.tasks[1].label, "occlusal.json");
  EXPECT_TRUE(list.tasks[2].builtin);
  EXPECT_TRUE(list.tasks.back().builtin);
  // A student starts on the first task that loads: the broken one comes first by name, but is passed over.
  EXPECT_EQ(firstCourseTask(list), dir.file("occlusal.json"));
  EXPECT_EQ(good->name, "occlusal");
}

TEST(CourseList, WithoutAFolderThereIsNoFirstCourseTask) { EXPECT_EQ(firstCourseTask(listCourse("")), ""); }

// The picker's line carries the student's record: best of how many, and passed.
TEST(CourseList, APickerLineShowsTheBestTheAttemptsAndPassed) {
  TaskChoice t;
  t.label = "class1.json";
  EXPECT_EQ(taskPickerLine(t), "class1.json");  // never tried
  t.attempts = 3;
  t.best = 81.6;
  EXPECT_EQ(taskPickerLine(t), "class1.json  best 82 of 3");
  t.passed = true;
  EXPECT_EQ(taskPickerLine(t), "class1.json  best 82 of 3, passed");
  t.error = "bad";
  EXPECT_EQ(taskPickerLine(t), "class1.json (does not load)");
}

// A tooth whose layers were synthesized from one surface says so in the picker; a measured one
// keeps its plain name. The list reads only the header.
TEST(CourseList, AToothWithSynthesizedLayersSaysSo) {
  test::TempDir dir;
  VolumeFileData d;
  d.frame = VolumeFrame::axisAligned(6, 0.1, {0, 0, 0});
  d.chunks.assign(1, 0x80000000u);  // level 6: one chunk, a tile of empty
  ASSERT_TRUE(writeVolumeFile(dir.file("measured.dvol"), d));
  d.layers_synthesized = true;
  d.layer_type = 1;
  ASSERT_TRUE(writeVolumeFile(dir.file("synth.dvol"), d));
  const CourseList list = listCourse(dir.path().string());
  const size_t builtin = size_t(kMaxLevel - kMinLevel + 1);
  ASSERT_EQ(list.teeth.size(), builtin + 2);
  EXPECT_EQ(list.teeth[builtin].label, "measured.dvol");
  EXPECT_EQ(list.teeth[builtin + 1].label, "synth.dvol (synthesized layers)");
  EXPECT_EQ(list.teeth[builtin + 1].path, dir.file("synth.dvol"));
}

TEST(CourseList, AFolderThatCannotBeReadSaysSoAndKeepsTheBuiltIns) {
  test::TempDir dir;
  const CourseList list = listCourse(dir.file("missing"));
  EXPECT_NE(list.error.find("missing"), std::string::npos) << list.error;
  EXPECT_EQ(list.teeth.size(), size_t(kMaxLevel - kMinLevel + 1));
  EXPECT_FALSE(list.tasks.empty());
}

TEST(CourseList, TheDefaultFolderIsAssetsTasksWhenItExists) {
  test::TempDir dir;
  EXPECT_EQ(defaultCourseFolder(dir.path().string()), "");
  std::filesystem::create_directories(dir.file("assets/tasks"));
  EXPECT_EQ(defaultCourseFolder(dir.path().string()), dir.file("assets/tasks"));
}

}  // namespace
}  // namespace dentsim::ui
