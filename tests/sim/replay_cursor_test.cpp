// The replay cursor: stepped to the end it is replaySession; back to the start and forward again it replays the same steps, forces and voxels as a straight run, and its edits keep a copy of the tooth equal.
#include "sim/replay_cursor.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sim/session_run.h"
#include "sim_fixtures.h"
#include "test_support.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

using test::molar;

// A short class I groove (about 1.3 s of drilling) recorded once for the suite.
const SessionRecording& recorded() {
  static const SessionRecording session = [] {
    const test::TempDir dir;
    const std::string file = dir.file("cursor.dses");
    ToothVolume live = molar();
    auto run = recordScriptedSession(live, defaultSimParams(), test::molarGroove(), file,
                                     test::molarSessionInfo("2026-11-27T10:00:00Z", ""), {});
    EXPECT_TRUE(run.ok()) << run.message();
    auto read = readSessionFile(file);
    EXPECT_TRUE(read.ok()) << read.message();
    return std::move(read).value();
  }();
  return session;
}

// The drill force of every step from the cursor's position to the end.
std::vector<Vec3> forcesToEnd(ReplayCursor& c) {
  std::vector<Vec3> forces;
  while (!c.atEnd()) {
    const StepReport& r = c.step();
    forces.push_back(r.stepped[0] ? r.tools[0].display.force : Vec3{});
  }
  return forces;
}

void expectSameForces(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].x, b[k].x) << "step " << k;
    ASSERT_EQ(a[k].y, b[k].y) << "step " << k;
    ASSERT_EQ(a[k].z, b[k].z) << "step " << k;
  }
}

TEST(ReplayCursor, SteppedToTheEndItEndsWhereReplaySessionDoes) {
  const SessionRecording& session = recorded();
  ASSERT_TRUE(session.end.has_value());
  ToothVolume straight = molar();
  auto replayed = replaySession(session, straight, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  ASSERT_TRUE(replayed->recorded_hash_matches);

  ToothVolume tooth = molar();
  auto cursor = ReplayCursor::open(session, tooth, {});
  ASSERT_TRUE(cursor.ok()) << cursor.message();
  ReplayCursor& c = **cursor;
  EXPECT_EQ(c.size(), session.steps.size());
  EXPECT_DOUBLE_EQ(c.duration(), double(session.steps.size()) / session.info.rate_hz);
  EXPECT_EQ(c.stepTo(c.size() / 2), c.size() / 2);
  EXPECT_EQ(c.stepTo(c.size() / 4), 0u) << "a target behind the cursor plays nothing";
  c.stepTo(c.size());
  ASSERT_TRUE(c.atEnd());
  const ReplayOutcome out = c.outcome();
  EXPECT_EQ(out.steps, replayed->steps);
  EXPECT_EQ(out.final_hash, replayed->final_hash);
  EXPECT_EQ(out.removed_mm3, replayed->removed_mm3);
  EXPECT_TRUE(out.recorded_hash_matches);
  EXPECT_EQ(out.force_mismatches, 0u);
  EXPECT_TRUE(tooth.voxels == straight.voxels);
}

TEST(ReplayCursor, BackToTheStartAndForwardAgainReplaysTheSameStepsAsAStraightRun) {
  const SessionRecording& session = recorded();
  ToothVolume straight_tooth = molar();
  auto straight = ReplayCursor::open(session, straight_tooth, {});
  ASSERT_TRUE(straight.ok()) << straight.message();
  const std::vector<Vec3> expected = forcesToEnd(**straight);
  const std::string expected_hash = (*straight)->outcome().final_hash;

  ToothVolume tooth = molar();
  auto cursor = ReplayCursor::open(session, tooth, {});
  ASSERT_TRUE(cursor.ok()) << cursor.message();
  ReplayCursor& c = **cursor;
  // Past the middle, where the bur is in the tooth, then back, twice; the second time from the end.
  for (size_t target : {c.size() * 2 / 3, c.size()}) {
    c.stepTo(target);
    ASSERT_EQ(c.position(), target);
    c.restart();
    EXPECT_EQ(c.position(), 0u);
    EXPECT_EQ(c.forceMismatches(), 0u);
    EXPECT_EQ(volumeHashHex(tooth.voxels, tooth.frame), session.info.tooth_hash) << "the starting tooth is back";
  }
  // Seek to a midpoint, then on to the end: every step's force is the straight run's.
  const size_t mid = c.size() / 2;
  std::vector<Vec3> forces;
  while (c.position() < mid) {
    const StepReport& r = c.step();
    forces.push_back(r.stepped[0] ? r.tools[0].display.force : Vec3{});
  }
  for (const Vec3& f : forcesToEnd(c)) forces.push_back(f);
  expectSameForces(forces, expected);
  EXPECT_EQ(c.outcome().final_hash, expected_hash);
  EXPECT_EQ(c.forceMismatches(), 0u);
  EXPECT_TRUE(c.outcome().recorded_hash_matches);
}

TEST(ReplayCursor, ItsEditsKeepACopyOfTheToothEqualThroughARestart) {
  const SessionRecording& session = recorded();
  ToothVolume tooth = molar();
  EditChannel edits(12);  // small: the cursor must stop for draining many times
  ReplayCursorOptions o;
  o.edits = &edits;
  auto cursor = ReplayCursor::open(session, tooth, o);
  ASSERT_TRUE(cursor.ok()) << cursor.message();
  ReplayCursor& c = **cursor;
  ToothVolume view = molar();
  std::vector<uint64_t> batch;
  std::vector<BrickCoord> dirty;
  auto drain = [&] {
    batch.clear();
    edits.drain(&batch);
    applyVoxelEdits(view.voxels, batch, &dirty);
  };
  auto playTo = [&](size_t target) {
    while (c.position() < target) {
      c.stepTo(target);
      drain();
    }
  };
  playTo(c.size() * 2 / 3);
  EXPECT_TRUE(view.voxels == tooth.voxels);
  EXPECT_FALSE(dirty.empty());
  c.restart();
  view = c.start();
  playTo(c.size());
  EXPECT_TRUE(view.voxels == tooth.voxels);
  EXPECT_EQ(c.loop().latest().deferred_cuts, 0u) << "no cut waited for room in the channel";
  EXPECT_TRUE(c.outcome().recorded_hash_matches);
}

}  // namespace
}  // namespace dentsim
