// `dentsim replay` in a window: under Xvfb on lavapipe it plays a short recorded session to the end (and through a seek back) and writes the same final volume and score as the headless replay.
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
    headless_ = new test::CommandResult(runDentsim("replay " + session() + " --headless -o " + dir_->file("head.dvol") +
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
  const auto r = test::runDentsimInXvfb("replay " + session() + " --speed 8 --exit-at-end --width 960 --height 600 -o " +
                                        file("win.dvol") + " --report " + file("win.json") + " --shot-at 0.3 " +
                                        file("win.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("in a window"), std::string::npos) << "the replay fell back to headless: " << r.output;
  EXPECT_NE(r.output.find("(the recording's)"), std::string::npos) << r.output;
  const std::vector<uint8_t> window = readBytes(file("win.dvol")), headless = readBytes(file("head.dvol"));
  ASSERT_FALSE(headless.empty());
  EXPECT_EQ(window, headless) << "the window's final volume is not the headless replay's";
  EXPECT_EQ(reportTotal(file("win.json")), reportTotal(file("head.json")));
  EXPECT_GE(reportTotal(file("head.json")), 0.0);
  auto shot = readPng(file("win.png"));
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
                                        from + " " + to + " -o " + file("seek.dvol"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("seek from"), std::string::npos) << "the seek never happened: " << r.output;
  EXPECT_EQ(readBytes(file("seek.dvol")), readBytes(file("head.dvol")));
}

TEST_F(ReplayWindowCli, ASpeedThatIsNotOnTheTransportIsRefused) {
  test::expectCleanFailure(runDentsim("replay " + session() + " --speed 3 -o " + file("no.dvol")), "--speed", "0.25, 0.5",
                           file("no.dvol"));
}

}  // namespace
}  // namespace dentsim
