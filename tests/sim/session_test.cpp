// Recorded sessions: the recorder's file replays to the same voxels byte for byte, with parameter changes, truncation, lost steps and the wrong tooth handled.
#include "sim/session_run.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "io/atomic_file.h"
#include "io/pen_playback.h"
#include "sim/haptic_loop.h"
#include "sim/session_recorder.h"
#include "sim/tool_library.h"
#include "sim_fixtures.h"
#include "test_support.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

using test::molar;

// This suite's sessions: caries removal on the molar.
SessionInfo testInfo() { return test::molarSessionInfo("2026-11-22T10:00:00Z", "caries_removal"); }

// The header recordScriptedSession fills in, for tests that drive the recorder themselves.
SessionInfo recorderInfo(const SimParams& params) {
  SessionInfo info = testInfo();
  info.rate_hz = params.device.rate_hz;
  info.drill_tool = "round_bur_010";
  info.tooth_hash = volumeHashHex(molar().voxels, molar().frame);
  info.tooth_level = test::kMolarLevel;
  info.voxel_mm = molar().frame.voxel_mm;
  info.params_json = simParamsJson(params);
  return info;
}

// The drill on a scripted groove, as the recorder tests drive it: the round bur's loop on `tooth`,
// its pen following `path` from the path's start. The tool is loaded first: the loop keeps a
// reference to it.
struct GrooveDrill {
  GrooveDrill(ToothVolume& tooth, const SimParams& params, const PenPath& path)
      : tool(loadToolModel("round_bur_010", params.point_shell).value()),
        loop(tooth.voxels, tooth.frame, params, tool, nullptr, nullptr),
        pen(path, PenRole::Drill) {
    loop.attach(PenRole::Drill, &pen);
    loop.placeTool(PenRole::Drill, path.samples.front().pose);
  }
  ToolModel tool;
  HapticLoop loop;
  ScriptedPen pen;
};

// The groove drilled on the molar while a recorder writes it: the recorder tests' whole set-up.
// The recorder is declared last, so it stops before the loop it records goes away.
struct RecordedGroove {
  ToothVolume live = molar();
  SimParams params = defaultSimParams();
  PenPath path = test::molarGroove();
  GrooveDrill drill{live, params, path};
  SessionInfo info = recorderInfo(params);
  uint64_t second = uint64_t(info.rate_hz);  // one second of loop time [steps]
  SessionRecorder recorder;
};

TEST(Session, ARecordedSessionReplaysToTheSameVoxelsByteForByte) {
  test::TempDir scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  auto run = recordScriptedSession(live, params, test::molarGroove(), scratch.file("s.dses"), testInfo(), {});
  ASSERT_TRUE(run.ok()) << run.message();
  EXPECT_GT(run->removed_mm3, 0.05);  // it did cut
  EXPECT_EQ(run->steps_lost, 0u);
  EXPECT_NE(run->final_hash, volumeHashHex(molar().voxels, molar().frame));

  auto session = readSessionFile(scratch.file("s.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  EXPECT_FALSE(fs::exists(scratch.file("s.dses.part")));
  EXPECT_EQ(session->steps.size(), run->steps);
  EXPECT_EQ(session->info.tooth_hash, volumeHashHex(molar().voxels, molar().frame));
  ASSERT_TRUE(session->end.has_value());
  EXPECT_EQ(session->end->final_hash, run->final_hash);

  // Twice, each from the untouched tooth: the same voxels as the live run, and the same file bytes.
  std::vector<uint8_t> saved[2];
  for (int k = 0; k < 2; ++k) {
    ToothVolume tooth = molar();
    auto replayed = replaySession(*session, tooth, {});
    ASSERT_TRUE(replayed.ok()) << replayed.message();
    EXPECT_EQ(replayed->steps, run->steps);
    EXPECT_EQ(replayed->final_hash, run->final_hash);
    EXPECT_TRUE(replayed->recorded_hash_matches);
    EXPECT_EQ(replayed->force_mismatches, 0u);
    EXPECT_TRUE(replayed->warnings.empty());
    EXPECT_TRUE(tooth.voxels == live.voxels);
    const std::string out = scratch.file("final" + std::to_string(k) + ".dvol");
    ASSERT_TRUE(saveTooth(out, tooth).ok());
    saved[k] = test::readBytes(out);
  }
  EXPECT_FALSE(saved[0].empty());
  EXPECT_EQ(saved[0], saved[1]);
}

TEST(Session, ASessionRecordedOnTheRealTimeThreadReplaysToo) {
  test::TempDir scratch;
  ToothVolume live = molar();
  ScriptedSessionOptions options;
  options.realtime = true;
  auto run = recordScriptedSession(live, defaultSimParams(), test::molarGroove(), scratch.file("rt.dses"), testInfo(),
                                   options);
  ASSERT_TRUE(run.ok()) << run.message();
  auto session = readSessionFile(scratch.file("rt.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  ToothVolume tooth = molar();
  auto replayed = replaySession(*session, tooth, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  EXPECT_EQ(replayed->final_hash, run->final_hash);
  EXPECT_EQ(replayed->force_mismatches, 0u);
  // Wall-clock stamps follow the loop's absolute deadlines: step k never runs before k periods
  // after the start (a slow machine makes it later, never earlier), and the stamps never go back.
  for (size_t k = 1; k < session->steps.size(); ++k) {
    ASSERT_GE(session->steps[k].wall_ns, session->steps[k - 1].wall_ns) << k;
    ASSERT_GE(session->steps[k].wall_ns, int64_t(k) * 1'000'000 - 100'000) << k;
  }
}

TEST(Session, AParameterChangeIsRecordedFromTheStepThatUsedItAndReplayed) {
  test::TempDir scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  SimParams harder = params;
  for (TissueParams& t : harder.tissues) t.hardness *= 0.25;  // a teacher slows the cutting down
  const PenPath path = test::molarGroove();
  constexpr uint64_t kSteps = 1200, kChangeAt = 700;
  {
    GrooveDrill drill(live, params, path);
    HapticLoop& loop = drill.loop;
    SessionRecorder recorder;
    const SessionInfo info = recorderInfo(params);
    ASSERT_TRUE(recorder.start(loop, scratch.file("p.dses"), info).ok());
    for (uint64_t k = 0; k < kSteps; ++k) {
      if (k == kChangeAt) recorder.setParams(harder);
      loop.step();
    }
    ASSERT_TRUE(recorder.finish(SessionEnd{kSteps, volumeHashHex(live.voxels, live.frame), "completed"}).ok());
  }
  auto session = readSessionFile(scratch.file("p.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  ASSERT_EQ(session->params.size(), 1u);
  EXPECT_EQ(session->params[0].serial, 1u);
  EXPECT_EQ(session->params[0].from_step, kChangeAt);
  EXPECT_EQ(session->steps[kChangeAt - 1].params_serial, 0u);
  EXPECT_EQ(session->steps[kChangeAt].params_serial, 1u);

  ToothVolume tooth = molar();
  auto replayed = replaySession(*session, tooth, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  EXPECT_TRUE(replayed->recorded_hash_matches);
  EXPECT_EQ(replayed->force_mismatches, 0u);

  // Without the change the same readings cut more: the record is what made the replay exact.
  SessionRecording unchanged = *session;
  unchanged.params.clear();
  for (SessionStep& s : unchanged.steps) s.params_serial = 0;
  ToothVolume other = molar();
  auto differs = replaySession(unchanged, other, {});
  ASSERT_TRUE(differs.ok()) << differs.message();
  EXPECT_NE(differs->final_hash, session->end->final_hash);
  EXPECT_GT(differs->removed_mm3, replayed->removed_mm3);
}

TEST(Session, ATruncatedSessionReplaysUpToItsLastWholeRecord) {
  test::TempDir scratch;
  ToothVolume live = molar();
  auto run = recordScriptedSession(live, defaultSimParams(), test::molarGroove(), scratch.file("t.dses"), testInfo(), {});
  ASSERT_TRUE(run.ok()) << run.message();
  // A crash mid-write: the file ends inside a record, about two thirds of the way through.
  std::vector<uint8_t> bytes = test::readBytes(scratch.file("t.dses"));
  bytes.resize(bytes.size() * 2 / 3 + 7);
  ASSERT_TRUE(writeFileAtomic(scratch.file("cut.dses"), bytes).ok());
  auto session = readSessionFile(scratch.file("cut.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  EXPECT_FALSE(session->truncation_warning.empty());
  EXPECT_FALSE(session->end.has_value());
  const size_t kept = session->steps.size();
  ASSERT_GT(kept, 100u);
  ASSERT_LT(kept, run->steps);

  ToothVolume tooth = molar();
  auto replayed = replaySession(*session, tooth, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  EXPECT_EQ(replayed->steps, kept);
  EXPECT_EQ(replayed->force_mismatches, 0u);
  EXPECT_FALSE(replayed->warnings.empty());

  // The same as the scripted drilling stopped after that many steps.
  ToothVolume reference = molar();
  const SimParams params = defaultSimParams();
  const PenPath path = test::molarGroove();
  GrooveDrill drill(reference, params, path);
  HapticLoop& loop = drill.loop;
  for (size_t k = 0; k < kept; ++k) loop.step();
  EXPECT_TRUE(reference.voxels == tooth.voxels);
}

TEST(Session, AnotherToothIsRefusedUnlessAllowed) {
  test::TempDir scratch;
  ToothVolume live = molar();
  auto run = recordScriptedSession(live, defaultSimParams(), test::molarGroove(), scratch.file("o.dses"), testInfo(), {});
  ASSERT_TRUE(run.ok()) << run.message();
  auto session = readSessionFile(scratch.file("o.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  ToothVolume other = molar();
  other.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Dentin));  // one voxel far from the cut
  auto refused = replaySession(*session, other, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("hash"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find(session->info.tooth_hash), std::string::npos) << refused.message();
  ReplayOptions allow;
  allow.allow_other_tooth = true;
  auto replayed = replaySession(*session, other, allow);
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  ASSERT_FALSE(replayed->warnings.empty());
  EXPECT_NE(replayed->warnings.front().find("hash"), std::string::npos);
  EXPECT_FALSE(replayed->recorded_hash_matches);  // the far voxel is still there
}

TEST(Session, StepsTheRecorderCouldNotKeepAreAGapWhereReplayStops) {
  test::TempDir scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  const PenPath path = test::molarGroove();
  uint64_t lost = 0;
  {
    GrooveDrill drill(live, params, path);
    HapticLoop& loop = drill.loop;
    SessionRecorder recorder(3);  // room for 8 steps: the loop outruns the writing thread
    const SessionInfo info = recorderInfo(params);
    ASSERT_TRUE(recorder.start(loop, scratch.file("g.dses"), info).ok());
    for (int k = 0; k < 2000; ++k) loop.step();
    ASSERT_TRUE(recorder.finish(SessionEnd{2000, volumeHashHex(live.voxels, live.frame), "completed"}).ok());
    lost = recorder.stepsLost();
    EXPECT_EQ(lost, loop.droppedRecords());
  }
  ASSERT_GT(lost, 0u);
  auto session = readSessionFile(scratch.file("g.dses"));
  ASSERT_TRUE(session.ok()) << session.message();
  ASSERT_FALSE(session->gaps.empty());
  uint64_t gap_steps = 0;
  for (const SessionGap& g : session->gaps) gap_steps += g.steps;
  EXPECT_EQ(gap_steps, lost);
  EXPECT_EQ(session->steps.size() + lost, 2000u);

  ToothVolume tooth = molar();
  auto replayed = replaySession(*session, tooth, {});
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  EXPECT_EQ(replayed->steps, session->gaps.front().first_step - session->steps.front().step);
  ASSERT_FALSE(replayed->warnings.empty());
  EXPECT_NE(replayed->warnings.back().find("lost steps"), std::string::npos) << replayed->warnings.back();
}

// A kill -9 keeps what the recorder handed to the kernel. A loop stepped back to back (lockstep,
// a scripted run) runs many times faster than the wall clock, so a flush every 200 ms of wall time
// once lost over 2 s of loop time; keepUp() holds the loop to within half a second of the kernel's copy.
TEST(Session, AKilledBackToBackRecordingLosesAtMostASecondOfLoopTime) {
  test::TempDir scratch;
  RecordedGroove g;
  HapticLoop& loop = g.drill.loop;
  SessionRecorder& recorder = g.recorder;
  const uint64_t second = g.second;
  ASSERT_TRUE(recorder.start(loop, scratch.file("k.dses"), g.info).ok());
  // Four seconds of loop time; after each second, the ".part" file as a kill would leave it now.
  for (int checkpoint = 1; checkpoint <= 4; ++checkpoint) {
    while (loop.stepsRun() < uint64_t(checkpoint) * second) {
      loop.step();
      recorder.keepUp();
    }
    auto part = readSessionFile(scratch.file("k.dses.part"));
    ASSERT_TRUE(part.ok()) << part.message();
    ASSERT_FALSE(part->steps.empty()) << "nothing on disk after " << loop.stepsRun() << " steps";
    EXPECT_TRUE(part->gaps.empty());
    // The last step on disk is within a second of loop time of the loop's last step.
    EXPECT_GE(part->steps.back().step + second, loop.stepsRun() - 1) << "at checkpoint " << checkpoint;
  }
  // No finish(): the recorder's destructor stands in for the kill, leaving the ".part" file.
}

// On the real-time thread the loop keeps the wall clock's pace: the recorder's own flushes keep
// the file within a second of loop time, without anyone calling keepUp(). Polled with a generous
// limit, so a loaded machine only makes it slower.
TEST(Session, ARealTimeRecordingOnDiskStaysWithinASecondOfTheLoop) {
  test::TempDir scratch;
  RecordedGroove g;
  HapticLoop& loop = g.drill.loop;
  SessionRecorder& recorder = g.recorder;
  const uint64_t second = g.second;
  ASSERT_TRUE(recorder.start(loop, scratch.file("r.dses"), g.info).ok());
  ASSERT_TRUE(loop.start().ok());
  bool within = false;
  uint64_t last_on_disk = 0, loop_steps = 0;
  for (int poll = 0; poll < 1000 && !within; ++poll) {  // up to 10 s
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    loop_steps = loop.stepsRun();  // before the read: the file is compared with the loop as it was then
    if (loop_steps < 2 * second) continue;
    auto part = readSessionFile(scratch.file("r.dses.part"));
    ASSERT_TRUE(part.ok()) << part.message();
    last_on_disk = part->steps.empty() ? 0 : part->steps.back().step;
    within = !part->steps.empty() && last_on_disk + second >= loop_steps - 1;
  }
  loop.stop();
  EXPECT_TRUE(within) << "last step on disk " << last_on_disk << ", loop at " << loop_steps;
}

}  // namespace
}  // namespace dentsim
