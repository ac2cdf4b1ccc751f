// Recorded sessions: the recorder's file replays to the same voxels byte for byte, with parameter changes, truncation, lost steps and the wrong tooth handled.
#include "sim/session_run.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/atomic_file.h"
#include "io/pen_playback.h"
#include "sim/builtin_tooth.h"
#include "sim/haptic_loop.h"
#include "sim/scripted_paths.h"
#include "sim/session_recorder.h"
#include "sim/tool_library.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

constexpr int kLevel = 7;  // the molar in 0.17 mm voxels: quick, and the bur still spans several

struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("dentsim_session_test_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string file(const std::string& name) const { return (dir / name).string(); }
};

const ToothVolume& molar() {
  static const ToothVolume tooth = [] {
    auto t = builtinMolarTooth(kLevel);
    EXPECT_TRUE(t.ok()) << t.message();
    return std::move(t).value();
  }();
  return tooth;
}

// A short class I groove: a third of a lap, about 1.3 s of drilling.
PenPath shortCavity(const ToothVolume& tooth) {
  CavityPathSettings s;
  s.laps = 0.3;
  auto path = cavityPreparationPath(tooth.voxels, tooth.frame, s);
  EXPECT_TRUE(path.ok()) << path.message();
  return path->path;
}

SessionInfo testInfo() {
  SessionInfo info;
  info.created_utc = "2026-11-22T10:00:00Z";
  info.program = "dentsim test";
  info.task = "caries_removal";
  info.tooth_source = "builtin:molar:7";
  return info;
}

// The header recordScriptedSession fills in, for tests that drive the recorder themselves.
SessionInfo recorderInfo(const SimParams& params) {
  SessionInfo info = testInfo();
  info.rate_hz = params.device.rate_hz;
  info.drill_tool = "round_bur_010";
  info.tooth_hash = volumeHashHex(molar().voxels, molar().frame);
  info.tooth_level = kLevel;
  info.voxel_mm = molar().frame.voxel_mm;
  info.params_json = simParamsJson(params);
  return info;
}

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Session, ARecordedSessionReplaysToTheSameVoxelsByteForByte) {
  Scratch scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  auto run = recordScriptedSession(live, params, shortCavity(molar()), scratch.file("s.dses"), testInfo(), {});
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
    saved[k] = fileBytes(out);
  }
  EXPECT_FALSE(saved[0].empty());
  EXPECT_EQ(saved[0], saved[1]);
}

TEST(Session, ASessionRecordedOnTheRealTimeThreadReplaysToo) {
  Scratch scratch;
  ToothVolume live = molar();
  ScriptedSessionOptions options;
  options.realtime = true;
  auto run = recordScriptedSession(live, defaultSimParams(), shortCavity(molar()), scratch.file("rt.dses"), testInfo(),
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
  Scratch scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  SimParams harder = params;
  for (TissueParams& t : harder.tissues) t.hardness *= 0.25;  // a teacher slows the cutting down
  const PenPath path = shortCavity(molar());
  auto drill = loadToolModel("round_bur_010", params.point_shell);
  ASSERT_TRUE(drill.ok());
  constexpr uint64_t kSteps = 1200, kChangeAt = 700;
  {
    HapticLoop loop(live.voxels, live.frame, params, *drill, nullptr, nullptr);
    ScriptedPen pen(path, PenRole::Drill);
    loop.attach(PenRole::Drill, &pen);
    loop.placeTool(PenRole::Drill, path.samples.front().pose);
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
  Scratch scratch;
  ToothVolume live = molar();
  auto run = recordScriptedSession(live, defaultSimParams(), shortCavity(molar()), scratch.file("t.dses"), testInfo(), {});
  ASSERT_TRUE(run.ok()) << run.message();
  // A crash mid-write: the file ends inside a record, about two thirds of the way through.
  std::vector<uint8_t> bytes = fileBytes(scratch.file("t.dses"));
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
  auto drill = loadToolModel("round_bur_010", params.point_shell);
  ASSERT_TRUE(drill.ok());
  const PenPath path = shortCavity(molar());
  HapticLoop loop(reference.voxels, reference.frame, params, *drill, nullptr, nullptr);
  ScriptedPen pen(path, PenRole::Drill);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, path.samples.front().pose);
  for (size_t k = 0; k < kept; ++k) loop.step();
  EXPECT_TRUE(reference.voxels == tooth.voxels);
}

TEST(Session, AnotherToothIsRefusedUnlessAllowed) {
  Scratch scratch;
  ToothVolume live = molar();
  auto run = recordScriptedSession(live, defaultSimParams(), shortCavity(molar()), scratch.file("o.dses"), testInfo(), {});
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
  Scratch scratch;
  ToothVolume live = molar();
  const SimParams params = defaultSimParams();
  const PenPath path = shortCavity(molar());
  auto drill = loadToolModel("round_bur_010", params.point_shell);
  ASSERT_TRUE(drill.ok());
  uint64_t lost = 0;
  {
    HapticLoop loop(live.voxels, live.frame, params, *drill, nullptr, nullptr);
    ScriptedPen pen(path, PenRole::Drill);
    loop.attach(PenRole::Drill, &pen);
    loop.placeTool(PenRole::Drill, path.samples.front().pose);
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

}  // namespace
}  // namespace dentsim
