// The student's start and the review after a score, end to end: `run --course DIR` opens on the course's first task and lists its tasks with the student's attempts and best; under Xvfb the Score page's Replay and Replay with the ghost buttons, clicked through ImGui, replay the attempt in the same window, the ghost beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/png_file.h"
#include "io/session_file.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJson;
using test::TempDir;

// Cuts fast, so that a 4 s pass at level 7 takes a visible bite (as window_cli_test's preset).
std::string writeFastPreset(const TempDir& dir) {
  const std::string preset = dir.file("fast.json");
  std::ofstream(preset) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                           R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
  return preset;
}

// docs/examples/occlusal_pass_tooth_frame.csv with the pass going `dx_mm` along x: the bur over the
// occlusal centre, down 0.4 mm at full speed, across, and up, in 4 s.
std::string writePass(const TempDir& dir, const std::string& name, double dx_mm) {
  const std::string path = dir.file(name);
  const std::string dx = std::to_string(dx_mm);
  std::ofstream(path) << "# frame: tooth\nt_s,pen,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,pedal\n"
                         "0,drill,0,0,21,1,0,0,0,0,0\n0.5,drill,0,0,21,1,0,0,0,0,1\n1.5,drill,0,0,18.6,1,0,0,0,0,1\n"
                         "3.5,drill," + dx + ",0,18.6,1,0,0,0,0,1\n4.0,drill," + dx + ",0,21,1,0,0,0,0,0\n";
  return path;
}

// The learning records' settings of a fresh student PC: config and outbox in the test's folder.
std::string records(const TempDir& dir, const std::string& student) {
  return (student.empty() ? std::string() : " --student " + student) + " --config " + dir.file("learning.json") +
         " --outbox " + dir.file("outbox.jsonl");
}

TEST(StudentStart, ACourseOpensOnItsFirstTaskAndListsItsTasksWithTheAttemptsAndBest) {
  const test::NoLeakCheckForGpuChild no_leak_check;  // headless runs still start the Vulkan driver
  TempDir dir;
  std::ofstream(dir.file("learning.json")) << "{}";
  // A course of two tasks: the class I cavity first by file name, then the caries removal.
  std::filesystem::create_directories(dir.file("course"));
  std::filesystem::copy_file(std::string(DENTSIM_SOURCE_DIR) + "/assets/tasks/class1_cavity.json", dir.file("course/a_class1.json"));
  std::filesystem::copy_file(std::string(DENTSIM_SOURCE_DIR) + "/assets/tasks/caries_removal.json", dir.file("course/b_caries.json"));
  const std::string pass = writePass(dir, "pass.csv", 1.5);
  auto attempt = [&](const std::string& out) {
    return test::runDentsim("run --headless --no-sound --course " + dir.file("course") + " --level 7 --params " +
                            writeFastPreset(dir) + " --pen-script " + pass + " --mirror none --score-at-end --shot 0.1 --out " +
                            dir.file(out) + records(dir, "s1001"));
  };
  const auto first = attempt("one");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  // No --task: the course's first task, not the built-in caries removal.
  const nlohmann::json shot = readJson(dir.file("one/shot-1.json"));
  ASSERT_FALSE(shot.is_discarded()) << first.output;
  EXPECT_EQ(shot["task"], "class1_cavity");
  // Before any attempt, the course's two tasks are listed, neither tried.
  EXPECT_NE(first.output.find("course " + dir.file("course") + " (student s1001):\n  a_class1.json  <- now\n  b_caries.json\n"),
            std::string::npos)
      << first.output;

  const auto second = attempt("two");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  // One attempt recorded at the class I task: its best is that attempt's score, of 1.
  const nlohmann::json score = readJson(dir.file("one/score.json"));
  ASSERT_FALSE(score.is_discarded());
  char best[64];
  std::snprintf(best, sizeof best, "  a_class1.json  best %.0f of 1", score["total"].get<double>());
  EXPECT_NE(second.output.find(std::string(best)), std::string::npos) << best << "\n" << second.output;
  EXPECT_NE(second.output.find("\n  b_caries.json\n"), std::string::npos) << second.output;
}

class ReviewWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!test::haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  }
  test::CommandResult runInXvfb(const std::string& args) {
    const test::NoLeakCheckForGpuChild no_leak_check;
    return test::runCommand("DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) + " " + args);
  }
  TempDir dir_;
};

TEST_F(ReviewWindow, AfterTheScoreReplayAndGhostOpenTheAttemptsReplayWithTheGhostBesideIt) {
  const test::NoLeakCheckForGpuChild no_leak_check;  // the professional's headless run starts the Vulkan driver
  std::ofstream(dir_.file("learning.json")) << "{}";
  const std::string preset = writeFastPreset(dir_);
  // The professional's pass goes mesially, the student's distally: the ghost stands apart.
  const auto pro = test::runDentsim("run --headless --no-sound --level 7 --params " + preset + " --pen-script " +
                                    writePass(dir_, "pro.csv", -1.5) + " --mirror none --out " + dir_.file("pro"));
  ASSERT_EQ(pro.exit_code, 0) << pro.output;
  const std::string out = dir_.file("student");
  const auto r = runInXvfb("run --level 7 --params " + preset + " --pen-script " + writePass(dir_, "student.csv", 1.5) +
                           " --mirror none --no-sound --lockstep --fps 10 --score-at-end --exit-at-end --ghost " +
                           dir_.file("pro/session.dses") + " --after-score-click review.replay --after-score-click review.ghost --after-score-click review.guided" +
                           " --review-shot 2.5 --width 1280 --height 800 --out " + out + records(dir_, "s1001"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Each button opened this attempt's recorded session, the second with the ghost.
  EXPECT_NE(r.output.find("review: replaying " + out + "/session.dses\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("review: replaying " + out + "/session.dses with the professional's ghost"), std::string::npos)
      << r.output;
  const nlohmann::json plain = readJson(out + "/review-1/shot-1.json"), ghost = readJson(out + "/review-2/shot-1.json");
  ASSERT_FALSE(plain.is_discarded()) << r.output;
  ASSERT_FALSE(ghost.is_discarded()) << r.output;
  EXPECT_TRUE(ghost["windowed"].get<bool>());
  // The replay's own panel (transport and timeline) along the bottom, at the replay time asked.
  for (const nlohmann::json* j : {&plain, &ghost}) {
    const auto panel = (*j)["panel_rect"];
    EXPECT_EQ(panel[0].get<int>(), 0);
    EXPECT_EQ(panel[2].get<int>(), 1280) << "the replay panel spans the window";
    EXPECT_EQ(panel[1].get<int>() + panel[3].get<int>(), 800) << "the replay panel sits at the bottom";
    EXPECT_NEAR((*j)["loop_time_s"].get<double>(), 2.5, 1e-9);
  }
  EXPECT_FALSE(plain.contains("ghost_bur_tip_px"));
  ASSERT_TRUE(ghost.contains("ghost_bur_tip_px"));

  // Lockstep replays draw the same frame at 2.5 s both times but for the ghost: every pixel that
  // differs lies on the ghost, the professional's bur and handpiece, which stand on and above its
  // tip, and there are enough of them to be a bur.
  auto a = readPng(out + "/review-1/shot-1.png"), b = readPng(out + "/review-2/shot-1.png");
  ASSERT_TRUE(a) << a.message();
  ASSERT_TRUE(b) << b.message();
  ASSERT_EQ(a->width, b->width);
  ASSERT_EQ(a->height, b->height);
  // The scene is drawn moved up by half the panel's height, which the shot's projection leaves out.
  const double gx = ghost["ghost_bur_tip_px"][0].get<double>();
  const double gy = ghost["ghost_bur_tip_px"][1].get<double>() - 0.5 * ghost["panel_rect"][3].get<double>();
  int near_ghost = 0, elsewhere = 0;
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) {
      const auto p = a->pixel(x, y), q = b->pixel(x, y);
      const int d = std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]);
      if (d <= 24) continue;
      if (std::fabs(x - gx) <= 60 && y <= gy + 20) ++near_ghost;
      else ++elsewhere;
    }
  EXPECT_GT(near_ghost, 150) << "ghost pixels around (" << gx << ", " << gy << ")";
  EXPECT_EQ(elsewhere, 0) << "pixels changed away from the ghost";

  // Retry with guidance: a new segment on the uncut tooth, recorded with the guide's spring in its header.
  EXPECT_NE(r.output.find("retry with guidance"), std::string::npos) << r.output;
  auto retry = readSessionFile(out + "/session-2.dses");
  ASSERT_TRUE(retry) << retry.message() << "\n" << r.output;
  EXPECT_FALSE(retry->info.guide_json.empty()) << "the retry is not guided";
  auto first = readSessionFile(out + "/session.dses");
  ASSERT_TRUE(first) << first.message();
  EXPECT_TRUE(first->info.guide_json.empty()) << "the attempt itself was not guided";
  EXPECT_EQ(retry->info.tooth_hash, first->info.tooth_hash) << "the retry starts on the uncut tooth";
}

}  // namespace
}  // namespace dentsim

namespace dentsim {
namespace {

// A run without --out records no session: the Replay button stays disabled (its tooltip says why),
// so the scripted click on it does nothing, and the run still ends.
TEST(ReviewWindowWithoutOut, TheReplayButtonIsDisabledAndTheClickDoesNothing) {
  if (!test::haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  TempDir dir;
  std::ofstream(dir.file("learning.json")) << "{}";
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runCommand("DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) +
                                  " run --level 7 --params " + writeFastPreset(dir) + " --pen-script " +
                                  writePass(dir, "student.csv", 1.5) +
                                  " --mirror none --no-sound --lockstep --fps 10 --score-at-end --exit-at-end"
                                  " --after-score-click review.replay" + records(dir, "s1001"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("score "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("review: replaying"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dentsim
