// `dentsim run --ghost`: the professional's bur shows where the professional's session had it at the student's task time, the ghost never cuts, and a session that does not read is one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/png_file.h"
#include "io/session_file.h"
#include "sim/pro_path.h"
#include "sim/tool_library.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
using test::readJson;
using test::TempDir;

test::CommandResult runGpu(const std::string& args) {
  const test::NoLeakCheckForGpuChild no_leak_check;
  return test::runCommand("DENTSIM_VALIDATION=1 " + std::string(DENTSIM_BINARY) + " " + args);
}

// A world point [mm] on a shot, through the view-projection its JSON records [px].
std::array<double, 2> project(const nlohmann::json& shot, const Vec3& p) {
  const nlohmann::json& m = shot["camera"]["view_proj"];
  double c[4];
  for (int r = 0; r < 4; ++r)
    c[r] = m[0 * 4 + r].get<double>() * p.x + m[1 * 4 + r].get<double>() * p.y + m[2 * 4 + r].get<double>() * p.z +
           m[3 * 4 + r].get<double>();
  return {(c[0] / c[3] * 0.5 + 0.5) * shot["width"].get<double>(), (c[1] / c[3] * 0.5 + 0.5) * shot["height"].get<double>()};
}

// The professional: the careful caries removal at level 6 with a preset that cuts ten times
// faster, no mirror. The student: the slow attempt on the same tooth, so that at the shot's task
// time the professional's bur has gone deeper than the student's. Each student run is taken with
// and without the ghost.
class GhostCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    std::ofstream(preset()) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                               R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
    pro_ = new test::CommandResult(runGpu("demo --headless --level 6 --mirror none --params " + preset() + " --out " + dir_->file("pro")));
  }
  static void TearDownTestSuite() {
    delete pro_;
    delete dir_;
  }
  static std::string preset() { return dir_->file("fast.json"); }
  static std::string proSession() { return dir_->file("pro/session.dses"); }
  static std::string student(const std::string& out, const std::string& extra) {
    return "run --headless --level 6 --mirror none --no-ui --width 480 --height 360 --params " + preset() +
           " --demo-script --attempt slow --shot " + std::to_string(kShotS) + " --out " + out + " " + extra;
  }

  static constexpr double kShotS = 0.8;
  static TempDir* dir_;
  static test::CommandResult* pro_;
};
TempDir* GhostCli::dir_ = nullptr;
test::CommandResult* GhostCli::pro_ = nullptr;

TEST_F(GhostCli, TheProfessionalsBurShowsWhereTheSessionHadItAndNeverCuts) {
  ASSERT_EQ(pro_->exit_code, 0) << pro_->output;
  const auto with = runGpu(student(dir_->file("with"), "--ghost " + proSession()));
  ASSERT_EQ(with.exit_code, 0) << with.output;
  const auto without = runGpu(student(dir_->file("without"), ""));
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_EQ(with.output.find("another tooth"), std::string::npos) << with.output;

  // The ghost never cuts: the student's final tooth (the whole slow attempt's cut) is the same,
  // byte for byte.
  EXPECT_GT(readJson(dir_->file("with/shot-final.json"))["removed_mm3"].get<double>(), 0.5) << "the student cut nothing";
  const std::vector<uint8_t> final_with = readBytes(dir_->file("with/final.dvol"));
  ASSERT_FALSE(final_with.empty());
  EXPECT_EQ(final_with, readBytes(dir_->file("without/final.dvol")));

  // Where ProPath says the professional's bur tip stood at the shot's task time.
  auto session = readSessionFile(proSession());
  ASSERT_TRUE(session.ok()) << session.message();
  auto path = ProPath::fromSession(*session, proSession());
  ASSERT_TRUE(path.ok()) << path.message();
  auto bur = loadToolModel(path->drillTool(), defaultSimParams().point_shell);
  ASSERT_TRUE(bur.ok()) << bur.message();
  const nlohmann::json shot = readJson(dir_->file("with/shot-1.json"));
  ASSERT_FALSE(shot.is_discarded());
  const Pose grip = path->at(shot["loop_time_s"].get<double>()).drill;
  const Vec3 tip = grip.position - grip.rotation.rotate(bur->grip_local);
  const Vec3 shank = tip + grip.rotation.rotate({0.0, 0.0, 6.0});
  const auto tip_px = project(shot, tip), shank_px = project(shot, shank);
  ASSERT_TRUE(shot.contains("ghost_bur_tip_px"));
  EXPECT_NEAR(shot["ghost_bur_tip_px"][0].get<double>(), tip_px[0], 1.5);
  EXPECT_NEAR(shot["ghost_bur_tip_px"][1].get<double>(), tip_px[1], 1.5);

  // The pictures differ only by the ghost: around the professional's bur, not the student's.
  auto a = readPng(dir_->file("with/shot-1.png")), b = readPng(dir_->file("without/shot-1.png"));
  ASSERT_TRUE(a) << a.message();
  ASSERT_TRUE(b) << b.message();
  ASSERT_EQ(a->width, b->width);
  int changed = 0, near_shank = 0, near_tip = 0;
  const double dx = shank_px[0] - tip_px[0], dy = shank_px[1] - tip_px[1];
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) {
      if (a->pixel(x, y) == b->pixel(x, y)) continue;
      ++changed;
      // Pixels along the bur's lowest 6 mm, from its tip to its shank, and around its tip.
      const double u = std::clamp(((x - tip_px[0]) * dx + (y - tip_px[1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      if (std::hypot(x - (tip_px[0] + u * dx), y - (tip_px[1] + u * dy)) < 6.0) ++near_shank;
      if (std::hypot(x - tip_px[0], y - tip_px[1]) < 8.0) ++near_tip;
    }
  EXPECT_GT(near_shank, 40) << "no ghost pixels along the professional's bur from (" << tip_px[0] << ", " << tip_px[1]
                            << ") to (" << shank_px[0] << ", " << shank_px[1] << "); " << changed << " changed";
  EXPECT_GT(near_tip, 10) << "no ghost pixels at the professional's bur tip (" << tip_px[0] << ", " << tip_px[1] << ")";
  // ... which is not where the student's bur is: those pixels are the professional's.
  EXPECT_GT(std::hypot(shot["bur_tip_px"][0].get<double>() - tip_px[0], shot["bur_tip_px"][1].get<double>() - tip_px[1]), 16.0);
  // Translucent: a pale blue blend over what was there, never the opaque steel or tooth colour.
  int bluer = 0;
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) {
      const auto p = a->pixel(x, y), q = b->pixel(x, y);
      if (p != q && int(p[2]) - int(p[0]) > int(q[2]) - int(q[0])) ++bluer;
    }
  EXPECT_GT(bluer, changed * 9 / 10);
}

TEST_F(GhostCli, NearestFollowStandsBesideTheStudentsBur) {
  ASSERT_EQ(pro_->exit_code, 0) << pro_->output;
  // Only the shots are looked at: the runs stop just after them.
  const std::string stop = " --exit-after " + std::to_string(kShotS + 0.05);
  const auto time = runGpu(student(dir_->file("time"), "--ghost " + proSession() + stop));
  ASSERT_EQ(time.exit_code, 0) << time.output;
  const auto nearest = runGpu(student(dir_->file("nearest"), "--ghost " + proSession() + " --ghost-follow nearest" + stop));
  ASSERT_EQ(nearest.exit_code, 0) << nearest.output;
  const auto gap = [](const nlohmann::json& shot) {
    return std::hypot(shot["ghost_bur_tip_px"][0].get<double>() - shot["bur_tip_px"][0].get<double>(),
                      shot["ghost_bur_tip_px"][1].get<double>() - shot["bur_tip_px"][1].get<double>());
  };
  const nlohmann::json t = readJson(dir_->file("time/shot-1.json")), n = readJson(dir_->file("nearest/shot-1.json"));
  ASSERT_TRUE(t.contains("ghost_bur_tip_px"));
  ASSERT_TRUE(n.contains("ghost_bur_tip_px"));
  // The slow student lags the professional by time; the nearest pose is beside the student's bur.
  EXPECT_LT(gap(n), gap(t)) << "nearest " << gap(n) << " px, time " << gap(t) << " px";
  EXPECT_LT(gap(n), 15.0);
}

TEST_F(GhostCli, ASessionRecordedOnAnotherToothShowsWithAWarning) {
  ASSERT_EQ(pro_->exit_code, 0) << pro_->output;
  const auto r = runGpu("run --headless --level 7 --mirror none --no-ui --width 160 --height 120 --exit-after 0.05 --ghost " +
                        proSession());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + proSession() + ": recorded on another tooth"), std::string::npos) << r.output;
}

TEST(GhostCliErrors, AGhostFileThatDoesNotReadIsOneLineNamingIt) {
  TempDir dir;
  const std::string junk = dir.file("junk.dses");
  std::ofstream(junk) << "not a session at all";
  for (const std::string& file : {junk, dir.file("missing.dses")}) {
    const auto r = runGpu("run --headless --level 6 --no-ui --exit-after 0.05 --ghost " + file);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_LT(r.exit_code, 128) << "a crash, not an error: " << r.output;
    // One line, naming the file.
    std::string out = r.output;
    while (!out.empty() && out.back() == '\n') out.pop_back();
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 0) << r.output;
    EXPECT_NE(out.find(file), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace dentsim
