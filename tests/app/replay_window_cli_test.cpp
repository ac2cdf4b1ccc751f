// `dentsim replay` in a window: under Xvfb on lavapipe it plays a short recorded session to the end (and through a seek back) and writes the same final volume and score as the headless replay, and the screenshots --shot asks for (the old --shot-at's too).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/png_file.h"
#include "io/session_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
using test::runDentsim;
using test::TempDir;

double reportTotal(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_discarded() || !j.contains("total") ? -1.0 : j["total"].get<double>();
}

// One short session for the suite: the first 4 s of the demo's path at level 7 with a preset that
// cuts ten times faster, no mirror (the bur is in the tooth for the last second or so); recorded
// headless, so that no window opens for it.
class ReplayWindowCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string preset = dir_->file("fast.json");
    std::ofstream(preset) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                             R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
    const test::NoLeakCheckForGpuChild no_leak_check;  // the run sets up its frames on the GPU
    demo_ = new test::CommandResult(
        runDentsim("run --headless --level 7 --mirror none --no-sound --demo-script --exit-after 4 --params " + preset +
                   " --out " + dir_->file("demo")));
    headless_ = new test::CommandResult(runDentsim("replay " + session() + " --headless --out " + dir_->file("head") +
                                                   " --report " + dir_->file("head.json")));
  }
  static void TearDownTestSuite() {
    delete headless_;
    delete demo_;
    delete dir_;
  }
  void SetUp() override {
    ASSERT_EQ(demo_->exit_code, 0) << demo_->output;
    ASSERT_EQ(headless_->exit_code, 0) << headless_->output;
    if (!test::haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  }
  static std::string session() { return dir_->file("demo") + "/session.dses"; }
  static std::string file(const std::string& name) { return dir_->file(name); }

  static TempDir* dir_;
  static test::CommandResult* demo_;
  static test::CommandResult* headless_;
};
TempDir* ReplayWindowCli::dir_ = nullptr;
test::CommandResult* ReplayWindowCli::demo_ = nullptr;
test::CommandResult* ReplayWindowCli::headless_ = nullptr;

TEST_F(ReplayWindowCli, PlayedToTheEndInTheWindowItWritesTheHeadlessReplaysVolumeAndScore) {
  const auto r = test::runDentsimInXvfb("replay " + session() + " --speed 8 --exit-at-end --width 960 --height 600 --out " +
                                        file("win") + " --report " + file("win.json") + " --shot 0.3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("in a window"), std::string::npos) << "the replay fell back to headless: " << r.output;
  EXPECT_NE(r.output.find("(the recording's)"), std::string::npos) << r.output;
  const std::vector<uint8_t> window = readBytes(file("win") + "/final.dvol"), headless = readBytes(file("head") + "/final.dvol");
  ASSERT_FALSE(headless.empty());
  EXPECT_EQ(window, headless) << "the window's final volume is not the headless replay's";
  EXPECT_EQ(reportTotal(file("win.json")), reportTotal(file("head.json")));
  EXPECT_GE(reportTotal(file("head.json")), 0.0);
  // The screenshot as `run --shot` names it: shot-1.png with shot-1.json beside it.
  std::ifstream facts_file(file("win") + "/shot-1.json");
  const nlohmann::json facts = nlohmann::json::parse(facts_file, nullptr, false);
  ASSERT_FALSE(facts.is_discarded());
  EXPECT_GE(facts["loop_time_s"].get<double>(), 0.3);
  EXPECT_TRUE(facts["windowed"].get<bool>());
  auto shot = readPng(file("win") + "/shot-1.png");
  ASSERT_TRUE(shot.ok()) << shot.message();
  EXPECT_EQ(shot->width, 960);
  EXPECT_EQ(shot->height, 600);
  // The timeline along the bottom: the contact band's green where the bur was in the tooth, and
  // the white playhead.
  int green = 0, white = 0;
  for (int y = shot->height - 170; y < shot->height; ++y)
    for (int x = 0; x < shot->width; ++x) {
      const auto p = shot->pixel(x, y);
      if (p[0] == 70 && p[1] == 170 && p[2] == 90) ++green;
      if (p[0] == 255 && p[1] == 255 && p[2] == 255) ++white;
    }
  EXPECT_GT(green, 20) << "no contact band on the timeline";
  EXPECT_GT(white, 20) << "no playhead on the timeline";
}

TEST_F(ReplayWindowCli, ASeekBackReCutsFromTheStartAndStillEndsOnTheSameVolume) {
  auto s = readSessionFile(session());
  ASSERT_TRUE(s.ok()) << s.message();
  const double duration = double(s->steps.size()) / s->info.rate_hz;
  ASSERT_GT(duration, 3.0);
  const std::string from = std::to_string(0.8 * duration), to = std::to_string(0.25 * duration);
  const auto r = test::runDentsimInXvfb("replay " + session() + " --speed 8 --exit-at-end --width 960 --height 600 --seek-at " +
                                        from + " " + to + " --out " + file("seek"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("seek from"), std::string::npos) << "the seek never happened: " << r.output;
  EXPECT_EQ(readBytes(file("seek") + "/final.dvol"), readBytes(file("head") + "/final.dvol"));
}

// The old spellings still work in the window: --shot-at writes its one picture where it says, -o the
// final volume, each with one line on stderr saying what replaced it.
TEST_F(ReplayWindowCli, TheOldShotAtAndOutputStillWorkAndSayTheyAreDeprecated) {
  const auto r = test::runDentsimInXvfb("replay " + session() + " --speed 8 --exit-at-end --width 960 --height 600 -o " +
                                        file("old.dvol") + " --shot-at 0.3 " + file("old.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dentsim replay: --shot-at SECONDS FILE is deprecated; use --shot SECONDS (--out DIR)\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("dentsim replay: -o/--output FILE is deprecated; use --out DIR"), std::string::npos) << r.output;
  EXPECT_EQ(readBytes(file("old.dvol")), readBytes(file("head") + "/final.dvol"));
  auto shot = readPng(file("old.png"));
  ASSERT_TRUE(shot.ok()) << shot.message();
  EXPECT_EQ(shot->width, 960);
  EXPECT_EQ(shot->height, 600);
}

TEST_F(ReplayWindowCli, ASpeedThatIsNotOnTheTransportIsRefused) {
  test::expectCleanFailure(runDentsim("replay " + session() + " --speed 3 --out " + file("no")), "--speed", "0.25, 0.5",
                           file("no"));
}

}  // namespace
}  // namespace dentsim
