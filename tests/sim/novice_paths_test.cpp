// Tests of the scripted attempts: the path edits (slower, stopped, joined) sample by sample, the names, and the careful caries path's plan on a small carious block.
#include "sim/novice_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dentsim {
namespace {

PenSample sample(double t, Vec3 tip, double pedal) {
  PenSample s;
  s.t_s = t;
  s.pose.position = tip;
  s.pedal = pedal;
  return s;
}

PenPath threeSamples() {
  PenPath p;
  p.samples = {sample(0.0, {0, 0, 5}, 0.0), sample(1.0, {1, 0, 4}, 1.0), sample(2.0, {2, 0, 4}, 1.0)};
  return p;
}

TEST(NovicePaths, WanderingPathMovesTheDrillSidewaysOnlyAndKeepsTheMirror) {
  // A drill held still at (1, 2, 3) for 3 s with the pedal down, and a mirror sample.
  PenPath still;
  PenSample a;
  a.pose.position = {1, 2, 3};
  a.pedal = 1.0;
  PenSample b = a;
  b.t_s = 3.0;
  PenSample m;
  m.pen = PenRole::Mirror;
  m.pose.position = {9, 9, 9};
  still.samples = {a, m, b};
  const PenPath w = wanderingPath(still, 0.5, 1.5);
  // Drill samples every 20 ms from 0 to 3 s (151), and the mirror's one.
  ASSERT_EQ(w.samples.size(), 152u);
  for (const PenSample& s : w.samples) {
    if (s.pen == PenRole::Mirror) {
      EXPECT_EQ(s, m);
      continue;
    }
    // x wanders with the 1.5 s period, y with 1.37 times it; z and the pedal as they were.
    EXPECT_NEAR(s.pose.position.x, 1.0 + 0.5 * std::sin(2 * std::numbers::pi * s.t_s / 1.5), 1e-12);
    EXPECT_NEAR(s.pose.position.y, 2.0 + 0.5 * std::sin(2 * std::numbers::pi * s.t_s / (1.5 * 1.37)), 1e-12);
    EXPECT_DOUBLE_EQ(s.pose.position.z, 3.0);
    EXPECT_DOUBLE_EQ(s.pedal, 1.0);
  }
  EXPECT_TRUE(std::is_sorted(w.samples.begin(), w.samples.end(),
                             [](const PenSample& x, const PenSample& y) { return x.t_s < y.t_s; }));
}

TEST(NovicePaths, SlowedPathStretchesTimeAndEasesThePedal) {
  const PenPath slow = slowedPath(threeSamples(), 3.0);
  ASSERT_EQ(slow.samples.size(), 3u);
  EXPECT_EQ(slow.samples[1].t_s, 3.0);
  EXPECT_EQ(slow.samples[2].t_s, 6.0);
  EXPECT_DOUBLE_EQ(slow.samples[1].pedal, 1.0 / 3.0);
  EXPECT_EQ(slow.samples[2].pose.position, (Vec3{2, 0, 4}));  // the same places
}

TEST(NovicePaths, StoppedPathLetsGoAndLifts) {
  const PenPath stopped = stoppedPath(threeSamples(), 1.5, 3.0, 0.3);
  ASSERT_EQ(stopped.samples.size(), 4u);
  EXPECT_EQ(stopped.samples[1].t_s, 1.0);
  EXPECT_EQ(stopped.samples[2].t_s, 1.0);       // pedal up where it stopped
  EXPECT_EQ(stopped.samples[2].pedal, 0.0);
  EXPECT_EQ(stopped.samples[3].t_s, 1.3);
  EXPECT_EQ(stopped.samples[3].pose.position, (Vec3{1, 0, 7}));
  EXPECT_TRUE(stoppedPath(threeSamples(), -1.0).samples.empty());
}

TEST(NovicePaths, JoinedPathsFollowOneAnother) {
  const PenPath joined = joinedPaths(threeSamples(), threeSamples(), 0.5);
  ASSERT_EQ(joined.samples.size(), 6u);
  EXPECT_EQ(joined.samples[3].t_s, 2.5);
  EXPECT_EQ(joined.samples[5].t_s, 4.5);
  EXPECT_TRUE(std::is_sorted(joined.samples.begin(), joined.samples.end(),
                             [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; }));
}

TEST(NovicePaths, NamesRoundTrip) {
  for (Attempt a : kAttempts) EXPECT_EQ(parseAttempt(attemptName(a)), a);
  EXPECT_FALSE(parseAttempt("sloppy").has_value());
  EXPECT_EQ(attemptNames(), "expert, overcut, undercut, heavy, slow, trench, tilted, token");
}

// A 64^3 grid of 0.1 mm voxels: enamel z 0..40 (4 mm), and a caries block 1 mm wide, 1.6 mm long
// and 0.8 mm deep whose top lies 0.6 mm under the surface.
struct CariousBlock {
  BrickVolume volume{6};
  VolumeFrame frame = VolumeFrame::axisAligned(6, 0.1, {0, 0, 0});
  CariousBlock() {
    for (uint32_t z = 0; z < 40; ++z)
      for (uint32_t y = 0; y < 64; ++y)
        for (uint32_t x = 0; x < 64; ++x) volume.setVoxel(x, y, z, makeVoxel(Material::Enamel));
    for (uint32_t z = 26; z < 34; ++z)
      for (uint32_t y = 27; y < 37; ++y)
        for (uint32_t x = 24; x < 40; ++x) volume.setVoxel(x, y, z, makeVoxel(Material::Caries));
  }
};

TEST(NovicePaths, CarefulCariesPathStaysOverTheLesionAndAboveItsFloor) {
  const CariousBlock b;
  const SimParams params = defaultSimParams();
  auto path = cariesRemovalPath(b.volume, b.frame, params, "round_bur_010");
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_NEAR(path->lesion_mm3, 1.6 * 1.0 * 0.8, 1e-9);
  EXPECT_GT(path->positions, 0);
  // The balls hold most of the caries, and healthy tissue only of the allowed zone: the enamel over
  // the lesion (1.6 x 1.0 x 0.6 mm) and the 0.2 mm leeway around both, under 2.0 x 1.4 x 1.6 mm in all.
  EXPECT_LE(path->planned_caries_mm3, path->lesion_mm3 + 1e-9);
  EXPECT_GE(path->planned_caries_mm3, 0.8 * path->lesion_mm3);
  EXPECT_LE(path->planned_healthy_mm3, 2.0 * 1.4 * 1.6 - path->planned_caries_mm3);
  const double floor_z = 2.6, grip = 19.0;
  for (const PenSample& s : path->path.samples) {
    const Vec3 tip = s.pose.position - Vec3{0, 0, grip};
    EXPECT_GE(tip.z, floor_z - 1e-9) << s.t_s;  // the pen never presses below the lesion's floor
    if (s.pedal > 0 && tip.z < 4.0) {            // cutting inside the tooth: over the lesion
      EXPECT_GE(tip.x, 2.4 - 1e-9) << s.t_s;
      EXPECT_LE(tip.x, 4.0 + 1e-9) << s.t_s;
      EXPECT_GE(tip.y, 2.7 - 1e-9) << s.t_s;
      EXPECT_LE(tip.y, 3.7 + 1e-9) << s.t_s;
    }
  }
  EXPECT_TRUE(std::is_sorted(path->path.samples.begin(), path->path.samples.end(),
                             [](const PenSample& a, const PenSample& c) { return a.t_s < c.t_s; }));
  // The heavy hand presses three times as deep and does not stop at the floor.
  auto heavy = cariesAttemptPath(Attempt::Heavy, b.volume, b.frame, params, "round_bur_010");
  ASSERT_TRUE(heavy.ok()) << heavy.message();
  double lowest = 1e9;
  for (const PenSample& s : heavy->samples) lowest = std::min(lowest, s.pose.position.z - grip);
  EXPECT_LT(lowest, floor_z - 1.0);
}

TEST(NovicePaths, CariesPathNeedsCariesAndAKnownBur) {
  BrickVolume empty(6);
  const VolumeFrame frame = VolumeFrame::axisAligned(6, 0.1, {0, 0, 0});
  const SimParams params = defaultSimParams();
  auto none = cariesRemovalPath(empty, frame, params, "round_bur_010");
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no caries"), std::string::npos) << none.message();
  const CariousBlock b;
  auto odd = cariesRemovalPath(b.volume, b.frame, params, "mirror_size4");
  ASSERT_FALSE(odd.ok());
  EXPECT_NE(odd.message().find("mirror_size4"), std::string::npos) << odd.message();
}

}  // namespace
}  // namespace dentsim
