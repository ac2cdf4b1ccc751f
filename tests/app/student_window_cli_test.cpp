// A student's first run at the window under Xvfb (lavapipe), with a course and no pen: the course's first task, the controls overlay and its instructions on screen, and a scripted mouse attempt that reaches the tooth with only the controls the overlay names.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/session_file.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJson;
using test::TempDir;

// "removed 0.0123 mm^3" from the run's summary line; -1 when there is none.
double removedMm3(const std::string& output) {
  const size_t at = output.rfind("removed ");
  if (at == std::string::npos) return -1.0;
  std::istringstream in(output.substr(at + 8));
  double v = -1.0;
  in >> v;
  return v;
}

class StudentWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!test::haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
    // A course of one task, copied from the shipped ones: the student's class I cavity.
    std::filesystem::create_directories(dir_.file("course"));
    std::filesystem::copy_file(std::string(DENTSIM_SOURCE_DIR) + "/assets/tasks/class1_cavity.json", dir_.file("course/class1_cavity.json"));
  }
  // A windowed run at level 7 in lockstep, the student's config folder fresh (first use), with
  // `input` as the scripted mouse and keys; shots at 0.2 s and at the end.
  test::CommandResult run(const std::string& out, const std::string& input) {
    const test::NoLeakCheckForGpuChild no_leak_check;
    return test::runCommand("XDG_CONFIG_HOME=" + dir_.file("config") + " XDG_DATA_HOME=" + dir_.file("data") +
                            " DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) +
                            " run --course " + dir_.file("course") + " --level 7 --lockstep --no-sound --width 1280 --height 800"
                            " --exit-after 2.0 --shot 0.2 --shot 1.9 --out " + dir_.file(out) + " " + input);
  }
  // The keys the overlay names, the same in both runs after the first: the turbine on (Space), then
  // the bur lowered along its axis by S, six presses 0.1 s apart.
  static std::string lowerAndDrill() {
    std::string keys = " --input 0.6 key:Space";
    for (int i = 0; i < 6; ++i) keys += " --input " + std::to_string(0.7 + 0.1 * i) + " key:S";
    return keys;
  }
  TempDir dir_;
};

TEST_F(StudentWindow, AFirstRunShowsTheCoursesTaskAndTheControlsAndBReachesTheTooth) {
  const auto r = run("first", "--input 0.5 key:B" + lowerAndDrill());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json shot = readJson(dir_.file("first/shot-1.json"));
  ASSERT_FALSE(shot.is_discarded()) << r.output;
  EXPECT_TRUE(shot["windowed"].get<bool>()) << "the run fell back to headless: " << r.output;
  EXPECT_EQ(shot["task"], "class1_cavity") << "the course's first task, not the built-in default";
  // The controls overlay is on screen, left of the panel, and leaves the tooth's middle clear.
  ASSERT_TRUE(shot.contains("help_rect")) << "no controls overlay on the first run";
  const auto help = shot["help_rect"], panel = shot["panel_rect"], tooth = shot["tooth_rect"];
  EXPECT_GT(help[2].get<int>(), 200);
  EXPECT_LE(help[0].get<int>() + help[2].get<int>(), panel[0].get<int>());
  const int tooth_mid_x = tooth[0].get<int>() + tooth[2].get<int>() / 2;
  EXPECT_LT(help[0].get<int>() + help[2].get<int>(), tooth_mid_x) << "the overlay covers the tooth's middle";
  // B, Space and six presses of S: the bur reached the tooth and cut.
  const double removed = removedMm3(r.output);
  EXPECT_GT(removed, 0.0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.file("config/dentsim/controls-seen"))) << "the overlay was never closed";
}

TEST_F(StudentWindow, WithoutBTheSameKeysStayInTheAirAndGotItIsRemembered) {
  // Got it clicked through ImGui, then the same keys without B: from the start 3 mm over the crown,
  // 0.6 mm of lowering touches nothing.
  const auto r = run("no_b", "--input 0.1 click:help.close" + lowerAndDrill());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(removedMm3(r.output), 0.0) << r.output;
  const nlohmann::json shot = readJson(dir_.file("no_b/shot-1.json"));
  ASSERT_FALSE(shot.is_discarded()) << r.output;
  EXPECT_FALSE(shot.contains("help_rect")) << "Got it closed it";
  EXPECT_TRUE(std::filesystem::exists(dir_.file("config/dentsim/controls-seen")));
  // The next run does not open it by itself.
  const auto again = run("again", "");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json next = readJson(dir_.file("again/shot-1.json"));
  ASSERT_FALSE(next.is_discarded()) << again.output;
  EXPECT_FALSE(next.contains("help_rect"));
}

// Guidance from the panel: the switch on the Tools page, then Stop and Reset start a guided segment
// whose session header holds the guide (the task's scripted professional), and the overlay's bar
// reads its pull once B has put the bur where the professional starts.
TEST_F(StudentWindow, TheGuidanceSwitchGuidesTheNextSegmentAndTheOverlayShowsItsPull) {
  const auto r = run("guided", "--help-overlay hide --input 0.1 click:page.tools --input 0.3 click:guidance"
                               " --input 0.5 click:stop --input 0.7 click:reset --input 0.9 key:B");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto first = readSessionFile(dir_.file("guided/session.dses"));
  auto second = readSessionFile(dir_.file("guided/session-2.dses"));
  ASSERT_TRUE(first.ok()) << first.message();
  ASSERT_TRUE(second.ok()) << second.message();
  EXPECT_TRUE(first->info.guide_json.empty()) << "the switch never changes the running segment";
  ASSERT_FALSE(second->info.guide_json.empty());
  EXPECT_NE(second->info.guide_json.find("the task's scripted professional"), std::string::npos);
  const nlohmann::json shot = readJson(dir_.file("guided/shot-2.json"));
  ASSERT_FALSE(shot.is_discarded()) << r.output;
  ASSERT_TRUE(shot.contains("guide_pull_n")) << "the segment at 1.9 s is guided";
  EXPECT_GT(shot["guide_pull_n"].get<double>(), 0.0);
  EXPECT_LE(shot["guide_pull_n"].get<double>(), 2.0 + 1e-9) << "the guide's cap";
}

TEST_F(StudentWindow, AClickOnAWidgetThatIsNotThereIsAOneLineError) {
  const auto r = run("bad", "--input 0.1 click:no_such_button");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no widget \"no_such_button\""), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dentsim
