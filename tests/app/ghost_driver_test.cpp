// GhostDriver: a professional's session file read as a ghost, the warning it earns on another tooth, and the pose it shows by task time and beside the student's bur, all without a window.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "app/ghost_driver.h"
#include "io/session_file.h"
#include "sim/sim_fixtures.h"
#include "sim/sim_params.h"
#include "test_sessions.h"
#include "test_support.h"
#include "volume/volume_hash.h"

namespace dentsim::app {
namespace {

// A one-brick tooth of 0.1 mm voxels: empty, or with one enamel voxel, so the two hash apart.
ToothVolume smallTooth(bool one_voxel) {
  ToothVolume t;
  t.frame = VolumeFrame::axisAligned(DS_MIN_LEVEL, 0.1, {0.0, 0.0, 0.0});
  t.voxels = BrickVolume{DS_MIN_LEVEL};
  if (one_voxel) t.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Enamel));
  return t;
}

// The professional's session on `tooth`, written to `file`: the drill pen moving along +x at
// 10 mm/s from the origin for 0.1 s (steps 0..100 at 1 kHz), told to render (0, 0, 2) N, so with a
// coupling of 1 N/mm its tool's grip stood 2 mm above the pen. No mirror.
std::string writeStroke(const test::TempDir& dir, const std::string& file, const ToothVolume& tooth,
                        const std::string& drill = "round_bur_010") {
  SessionRecording s = test::straightStroke(1.0, drill);
  const SessionInfo stroke = s.info;  // its rate and parameters, under a header made for `tooth`
  s.info = test::handMadeSessionInfo(volumeHashHex(tooth.voxels, tooth.frame), DS_MIN_LEVEL, 0.1, drill);
  s.info.rate_hz = stroke.rate_hz;
  s.info.params_json = stroke.params_json;
  s.end = SessionEnd{101, s.info.tooth_hash, "completed"};
  const std::vector<uint8_t> bytes = encodeSession(s);
  std::ofstream(dir.file(file), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  return dir.file(file);
}

TEST(GhostDriver, OnTheToothItWasRecordedOnLoadsWithoutAWarning) {
  test::TempDir dir;
  const ToothVolume tooth = smallTooth(false);
  auto g = GhostDriver::load(writeStroke(dir, "pro.dses", tooth), defaultSimParams().point_shell, tooth);
  ASSERT_TRUE(g) << g.message();
  EXPECT_TRUE(g->warnings().empty());
  EXPECT_EQ(g->source(), dir.file("pro.dses"));
  EXPECT_EQ(g->path().drillTool(), "round_bur_010");
  EXPECT_TRUE(g->path().mirrorTool().empty());
  // Steps 0, 10, ..., 100 kept: eleven poses (ProPath samples 100 a second).
  EXPECT_EQ(g->path().poses().size(), 11u);
}

TEST(GhostDriver, OnAnotherToothWarnsOnceNamingBothHashes) {
  test::TempDir dir;
  const ToothVolume recorded = smallTooth(false), other = smallTooth(true);
  const std::string recorded_hash = volumeHashHex(recorded.voxels, recorded.frame);
  const std::string other_hash = volumeHashHex(other.voxels, other.frame);
  ASSERT_NE(recorded_hash, other_hash);
  auto g = GhostDriver::load(writeStroke(dir, "pro.dses", recorded), defaultSimParams().point_shell, other);
  // Still a ghost: only the cut it shows is not this tooth's.
  ASSERT_TRUE(g) << g.message();
  ASSERT_EQ(g->warnings().size(), 1u);
  EXPECT_EQ(g->warnings()[0], dir.file("pro.dses") + ": recorded on another tooth (hash " + recorded_hash +
                                  ") than this run's (hash " + other_hash + "): the ghost shows a cut made on that one");
}

TEST(GhostDriver, FollowsTimeAlongTheSessionsOwnSteps) {
  test::TempDir dir;
  const ToothVolume tooth = smallTooth(false);
  const std::string file = writeStroke(dir, "pro.dses", tooth);
  auto g = GhostDriver::load(file, defaultSimParams().point_shell, tooth);
  ASSERT_TRUE(g) << g.message();
  auto session = readSessionFile(file);
  ASSERT_TRUE(session) << session.message();
  // Before any follow: the start, step 0's pen plus 2 N over 1 N/mm.
  EXPECT_NEAR(g->now().drill.position.x, 0.0, 1e-12);
  EXPECT_NEAR(g->now().drill.position.z, 2.0, 1e-12);
  // At a sampled time the pose is the step's own: step k at k ms, its pen plus the force over k.
  for (const uint64_t k : {30u, 60u, 100u}) {
    const SessionStep& step = session->steps[k];
    const ProPose& p = g->followTime(double(k) / 1000.0);
    EXPECT_NEAR(p.drill.position.x, step.reading[0].grip.position.x + step.force_n[0].x, 1e-12) << "step " << k;
    EXPECT_NEAR(p.drill.position.z, step.reading[0].grip.position.z + step.force_n[0].z, 1e-12) << "step " << k;
    EXPECT_TRUE(p.drill_held);
  }
  // Between samples (25 ms, between steps 20 and 30): halfway along, x = 0.25 mm.
  EXPECT_NEAR(g->followTime(0.025).drill.position.x, 0.25, 1e-12);
  // Past the end the last pose holds (step 100, x = 1 mm); before the start, the first.
  EXPECT_NEAR(g->followTime(5.0).drill.position.x, 1.0, 1e-12);
  EXPECT_NEAR(g->followTime(-1.0).drill.position.x, 0.0, 1e-12);
}

TEST(GhostDriver, FollowsTheNearestPoseForwardUntilRestarted) {
  test::TempDir dir;
  const ToothVolume tooth = smallTooth(false);
  auto g = GhostDriver::load(writeStroke(dir, "pro.dses", tooth), defaultSimParams().point_shell, tooth);
  ASSERT_TRUE(g) << g.message();
  // The student's grip at (0.52, 1, 2): nearest the pose at x = 0.5 mm, the one at 50 ms.
  const Pose near_half{{0.52, 1.0, 2.0}, Quat{}};
  EXPECT_DOUBLE_EQ(g->followNearest(near_half, {0.0, 0.0, 0.0}).t_s, 0.05);
  // The grip point is where the student's tool frame puts its grip: 0.3 mm back along x from the
  // frame's origin at (1.0, 0, 2) is x = 0.7 mm, the pose at 70 ms.
  EXPECT_DOUBLE_EQ(g->followNearest(Pose{{1.0, 0.0, 2.0}, Quat{}}, {-0.3, 0.0, 0.0}).t_s, 0.07);
  // The search runs forward from its last answer, so going back to x = 0.52 stays at 70 ms ...
  EXPECT_DOUBLE_EQ(g->followNearest(near_half, {0.0, 0.0, 0.0}).t_s, 0.07);
  // ... until a new segment starts it again from the professional's start.
  g->restart();
  EXPECT_DOUBLE_EQ(g->followNearest(near_half, {0.0, 0.0, 0.0}).t_s, 0.05);
}

TEST(GhostDriver, RefusesInOneLineNamingTheFile) {
  test::TempDir dir;
  const ToothVolume tooth = smallTooth(false);
  auto missing = GhostDriver::load(dir.file("none.dses"), defaultSimParams().point_shell, tooth);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.message().find(dir.file("none.dses")), std::string::npos) << missing.message();
  // A drill the simulator does not know: named as the professional's.
  const std::string file = writeStroke(dir, "odd.dses", tooth, "no_such_bur");
  auto odd = GhostDriver::load(file, defaultSimParams().point_shell, tooth);
  ASSERT_FALSE(odd);
  EXPECT_EQ(odd.message().rfind(file + ": the professional's drill: ", 0), 0u) << odd.message();
  EXPECT_EQ(odd.message().find('\n'), std::string::npos) << odd.message();
}

}  // namespace
}  // namespace dentsim::app
