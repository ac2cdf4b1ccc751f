// The simulator's tasks, course folder and teacher mode from the command line, and how its runs end: a task's fixed first view (under Xvfb on lavapipe), Record as ideal end to end, the windowed demo closing by itself, and runs cut short naming only the files they wrote and no score of -1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/session_file.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJson;
using test::TempDir;

using test::haveXvfb;

// A fast preset: the scripted paths at level 7 take a second or two of loop time.
std::string writeFastPreset(const TempDir& dir) {
  const std::string preset = dir.file("fast.json");
  std::ofstream(preset) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                           R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
  return preset;
}

// Every file a run says it wrote ("wrote PATH" lines, and "wrote DIR: a b c" from the demo).
std::vector<std::string> claimedFiles(const std::string& output) {
  std::vector<std::string> files;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    if (!line.starts_with("wrote ")) continue;
    const std::string rest = line.substr(6);
    const size_t colon = rest.find(": ");
    if (colon == std::string::npos) {
      files.push_back(rest);
      continue;
    }
    std::istringstream names(rest.substr(colon + 2));
    for (std::string n; names >> n;) files.push_back((std::filesystem::path(rest.substr(0, colon)) / n).string());
  }
  return files;
}

// A line that ends "score N.NN", as a scored run's last line does. (Not std::regex: GCC's -O1
// sanitizer build warns falsely inside <regex>, and that build treats warnings as errors.)
bool hasScoreLine(const std::string& output) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    const size_t at = line.rfind("score ");
    if (at == std::string::npos || (at > 0 && line[at - 1] != ' ')) continue;
    const std::string n = line.substr(at + 6);
    const size_t dot = n.find('.');
    if (dot == 0 || dot == std::string::npos || n.size() != dot + 3) continue;
    if (std::all_of(n.begin(), n.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.'; })) return true;
  }
  return false;
}

// A run that ended early: no score of -1 anywhere, and every file it names is on disk.
void expectHonestEnding(const std::string& output) {
  EXPECT_EQ(output.find("-1.00"), std::string::npos) << output;
  EXPECT_EQ(output.find("score -1"), std::string::npos) << output;
  for (const std::string& f : claimedFiles(output)) EXPECT_TRUE(std::filesystem::exists(f)) << f << " is named but missing:\n" << output;
}

class CourseWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  }
  test::CommandResult runInXvfb(const std::string& args, const std::string& prefix = "") {
    const test::NoLeakCheckForGpuChild no_leak_check;
    return test::runCommand("DENTSIM_VALIDATION=1 " + prefix + "xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) + " " + args);
  }
};

// `--task class1_indirect` starts the indirect-vision task by name: its fixed view from buccal below
// the crown, so the eye is under the occlusal surface, and the mirror held where the eye sees it.
// The built-in class I task starts free, from above.
TEST_F(CourseWindow, ATaskPickedOnTheCommandLineStartsWithItsView) {
  TempDir dir;
  const std::string common = "run --level 7 --lockstep --no-sound --shot 0.05 --exit-after 0.1 --width 1280 --height 800 --out ";
  const auto r = runInXvfb(common + dir.file("indirect") + " --task class1_indirect");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json shot = readJson(dir.file("indirect/shot-1.json"));
  ASSERT_FALSE(shot.is_discarded()) << r.output;
  EXPECT_TRUE(shot["windowed"].get<bool>()) << "the run fell back to headless: " << r.output;
  EXPECT_EQ(shot["task"], "class1_indirect");
  EXPECT_TRUE(shot["camera"]["fixed"].get<bool>());
  EXPECT_NEAR(shot["camera"]["pitch_deg"].get<double>(), -25.0, 1e-3) << "the task file's elevation";
  EXPECT_LT(shot["camera"]["eye_mm"][2].get<double>(), shot["tooth_top_mm"].get<double>()) << "the eye is below the crown";
  // The mirror is on screen and faces the eye.
  ASSERT_TRUE(shot.contains("mirror_centre_px")) << r.output;
  EXPECT_TRUE(shot["mirror_faces_eye"].get<bool>());
  const double mx = shot["mirror_centre_px"][0], my = shot["mirror_centre_px"][1];
  EXPECT_GT(mx, 0);
  EXPECT_LT(mx, 890) << "left of the panel";
  EXPECT_GT(my, 0);
  EXPECT_LT(my, 800);

  const auto free_run = runInXvfb(common + dir.file("free") + " --task class1_cavity");
  ASSERT_EQ(free_run.exit_code, 0) << free_run.output;
  const nlohmann::json free_shot = readJson(dir.file("free/shot-1.json"));
  ASSERT_FALSE(free_shot.is_discarded()) << free_run.output;
  EXPECT_FALSE(free_shot["camera"]["fixed"].get<bool>());
  EXPECT_GT(free_shot["camera"]["eye_mm"][2].get<double>(), free_shot["tooth_top_mm"].get<double>());
}

// Without --stay, the windowed demo prints its score and closes by itself after the score screen.
TEST_F(CourseWindow, TheWindowedDemoPrintsItsScoreAndClosesByItself) {
  TempDir dir;
  const std::string out = dir.file("demo");
  // `timeout` only turns a window that never closes into a failure instead of a hung suite.
  const auto r = runInXvfb("demo --level 7 --no-sound --params " + writeFastPreset(dir) + " --out " + out, "timeout 600 ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("window on"), std::string::npos) << "the demo ran in the window: " << r.output;
  EXPECT_TRUE(hasScoreLine(r.output)) << r.output;
  EXPECT_NE(r.output.find("caries removal score"), std::string::npos) << "the score's line, printed when scored: " << r.output;
  expectHonestEnding(r.output);
  for (const char* f : {"initial.dvol", "session.dses", "final.dvol", "final.ply", "score.json", "score.png"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
}

// A windowed demo cut short (here by --exit-after, as by closing the window) is not scored, says
// why, and names only the files it wrote: no score.json, no score.png.
TEST_F(CourseWindow, ADemoCutShortSaysNotScoredAndNamesOnlyItsFiles) {
  TempDir dir;
  const std::string out = dir.file("short");
  const auto r = runInXvfb("demo --level 7 --no-sound --exit-after 0.2 --out " + out, "timeout 600 ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("not scored: "), std::string::npos) << r.output;
  expectHonestEnding(r.output);
  EXPECT_FALSE(std::filesystem::exists(out + "/score.json"));
  const std::vector<std::string> claimed = claimedFiles(r.output);
  EXPECT_EQ(std::count(claimed.begin(), claimed.end(), out + "/score.json"), 0) << r.output;
  EXPECT_EQ(std::count(claimed.begin(), claimed.end(), out + "/session.dses"), 1) << r.output;
}

// Ctrl-C on a run with the mouse as the pen (which never ends by itself): the run ends, names
// nothing missing, prints no -1, and finishes its session readable, as when the window is closed.
TEST_F(CourseWindow, ARunInterruptedByCtrlCNamesOnlyItsFilesAndFinishesItsSession) {
  TempDir dir;
  const std::string out = dir.file("interrupted");
  // The signal goes to dentsim alone (the X server stays up), first 20 s after it started. A
  // background job of a script starts with SIGINT ignored, so a signal that lands before dentsim
  // installs its handler (a slow start under a sanitizer) is lost: it is sent again every 5 s.
  // After 10 minutes the run is killed, so that a run deaf to Ctrl-C fails here instead of hanging.
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runCommand(
      "DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' sh -c '" + std::string(DENTSIM_BINARY) +
      " run --level 7 --no-sound --out " + out +
      // A child that has exited stays a zombie until `wait`, and kill succeeds on it: state Z is not running.
      R"( & pid=$!; alive() { s=$(cut -d" " -f3 /proc/$pid/stat 2>/dev/null); [ -n "$s" ] && [ "$s" != Z ]; }; )"
      R"(sleep 20; n=0; while alive && [ $n -lt 120 ]; do kill -INT $pid; sleep 5; n=$((n+1)); done; )"
      R"(if alive; then kill -KILL $pid; echo "still running after 10 minutes of Ctrl-C"; fi; wait $pid')");
  EXPECT_EQ(r.output.find("still running after"), std::string::npos) << r.output;
  expectHonestEnding(r.output);
  ASSERT_NE(r.output.find("not scored: interrupted (Ctrl-C)"), std::string::npos) << r.output;
  EXPECT_EQ(r.exit_code, 0) << r.output;
  auto session = readSessionFile(out + "/session.dses");
  ASSERT_TRUE(session.ok()) << session.message();
  EXPECT_TRUE(session->end.has_value()) << "the session was finished with its end record";
}

// The score picture stands beside the tooth, not over it (headless: the panel is drawn there too).
TEST(CourseCli, TheScorePictureDoesNotCoverTheTooth) {
  TempDir dir;
  const std::string out = dir.file("scored");
  const test::NoLeakCheckForGpuChild no_leak_check;
  // The scored cut is also a learning record (docs/LEARNING_RECORDS.md): the simulator's hook.
  const std::string config = dir.file("learning.json"), outbox = dir.file("outbox.jsonl");
  std::ofstream(config) << "{}";
  const auto r = test::runDentsim("run --headless --no-sound --level 7 --params " + writeFastPreset(dir) +
                                  " --demo-script --score-at-end --width 1280 --height 800 --out " + out +
                                  " --student s1001 --course-id cons-101 --config " + config + " --outbox " + outbox);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream records(outbox);
  std::string line, extra;
  ASSERT_TRUE(std::getline(records, line)) << r.output;
  EXPECT_FALSE(std::getline(records, extra)) << "one scored cut, one statement";
  const nlohmann::json statement = nlohmann::json::parse(line);
  EXPECT_EQ(statement["object"]["id"], "https://dentsim.invalid/xapi/courses/cons-101/tasks/caries_removal");
  EXPECT_EQ(statement["actor"]["account"]["name"], "s1001");
  EXPECT_TRUE(statement["result"]["extensions"]["https://dentsim.invalid/xapi/extensions/session-hash"].is_string());
  const nlohmann::json shot = readJson(out + "/shot-final.json");
  ASSERT_FALSE(shot.is_discarded()) << r.output;
  ASSERT_TRUE(shot.contains("score_image_rect")) << shot.dump(1);
  ASSERT_TRUE(shot.contains("tooth_rect")) << shot.dump(1);
  const auto& p = shot["score_image_rect"];
  const auto& t = shot["tooth_rect"];
  const int px = p[0], py = p[1], pw = p[2], ph = p[3], tx = t[0], ty = t[1], tw = t[2], th = t[3];
  const bool overlap = px < tx + tw && tx < px + pw && py < ty + th && ty < py + ph;
  EXPECT_FALSE(overlap) << "picture " << p.dump() << ", tooth " << t.dump();
  EXPECT_LE(px + pw, shot["panel_rect"][0].get<int>()) << "and not over the panel";
}

// Teacher mode end to end, headless: the scripted class I cut of a course's task file is recorded
// as the file's ideal (session and final tooth beside it, the task rewritten with their hashes),
// and the same cut then scores no under-cut and no over-cut against it.
TEST(CourseCli, RecordAsIdealMakesTheSegmentTheTaskFilesIdeal) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("course"));
  const std::string task = dir.file("course/my_class1.json");
  std::ofstream(task) << R"({"format":"dentsim-task","version":2,"name":"my_class1","kind":"cavity","title":"Class I",)"
                         R"("tooth":"builtin:molar","level":7,"tools":{"drill":"fissure_bur_010","mirror":"mirror_size4"},)"
                         R"("target_s":600,"force_error_n":3.0,"insertion_axis":[0,0,1],"leeway_mm":0.2,"pulp_exposure_cap":50,)"
                         R"("ideal":{"kind":"builtin_path","path":"class1_cavity"}})";
  const std::string out = dir.file("out");
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runDentsim("run --headless --no-sound --task " + task + " --course " + dir.file("course") + " --params " +
                                  writeFastPreset(dir) + " --demo-script --teacher --record-ideal-at-end --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ideal recorded in " + task), std::string::npos) << r.output;
  const nlohmann::json rewritten = readJson(task);
  ASSERT_FALSE(rewritten.is_discarded());
  EXPECT_EQ(rewritten["ideal"]["kind"], "session") << rewritten.dump(1);
  EXPECT_EQ(rewritten["ideal"]["path"], "my_class1.ideal.dses");
  EXPECT_FALSE(rewritten["ideal"]["final_hash"].get<std::string>().empty());
  EXPECT_TRUE(std::filesystem::exists(dir.file("course/my_class1.ideal.dses")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("course/my_class1.ideal.dvol")));
  expectHonestEnding(r.output);

  // Scored against its own ideal, the same cut is neither short of it nor beyond it.
  const auto score = test::runDentsim("score --task " + task + " --initial " + out + "/initial.dvol --final " + out +
                                      "/final.dvol -o " + dir.file("score.json"));
  ASSERT_EQ(score.exit_code, 0) << score.output;
  EXPECT_NE(score.output.find("under-cut 0.000 mm^3, over-cut 0.000 mm^3"), std::string::npos) << score.output;

  // A built-in task cannot take an ideal: the run says so and changes nothing.
  const auto builtin = test::runDentsim("run --headless --no-sound --task class1_cavity --level 7 --params " +
                                        writeFastPreset(dir) + " --demo-script --teacher --record-ideal-at-end --out " +
                                        dir.file("out2"));
  ASSERT_EQ(builtin.exit_code, 0) << builtin.output;
  EXPECT_NE(builtin.output.find("not recorded: the task is built in"), std::string::npos) << builtin.output;
}

}  // namespace
}  // namespace dentsim
