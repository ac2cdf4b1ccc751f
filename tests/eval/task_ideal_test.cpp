// Tests for src/eval/task_ideal.cpp and the identity checks of idealForTask: an ideal recorded on one tooth is not scored against another, a changed file is named, and the keys a task leaves to its professional are set from the session.
#include "eval/task_ideal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "eval/cut_score.h"
#include "eval_fixtures.h"
#include "io/file_hash.h"
#include "io/session_file.h"
#include "test_sessions.h"
#include "test_support.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

struct Fixture {
  test::TempDir dir;
  ToothVolume initial = test::enamelSlab();
  ToothVolume ideal = test::enamelSlab();
  Task task = test::cavityTask();
  Fixture() {
    test::setBox(ideal, {4, 4, 4}, {12, 12, 8}, makeVoxel(Material::Empty));
    EXPECT_TRUE(saveTooth(dir.file("ideal.dvol"), ideal).ok());
    task.ideal = idealVolumeFile(dir.file("ideal.dvol"));
    task.ideal->initial_hash = volumeHashHex(initial.voxels, initial.frame);
    task.ideal->final_hash = volumeHashHex(ideal.voxels, ideal.frame);
  }
};

TEST(TaskIdeal, TheRecordedIdentityLetsTheIdealThrough) {
  Fixture f;
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, f.initial, &warnings);
  ASSERT_TRUE(made.ok()) << made.message();
  EXPECT_TRUE(made->voxels == f.ideal.voxels);
}

TEST(TaskIdeal, AnotherToothIsNamedNotScored) {
  Fixture f;
  ToothVolume other = f.initial;
  other.voxels.setVoxel(0, 0, 0, makeVoxel(Material::Dentin));  // one voxel differs
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, other, &warnings);
  ASSERT_FALSE(made.ok());
  EXPECT_NE(made.message().find("ideal: recorded on another tooth (hash " + f.task.ideal->initial_hash + ")"), std::string::npos)
      << made.message();
  EXPECT_NE(made.message().find("dentsim task set-ideal"), std::string::npos) << made.message();
}

TEST(TaskIdeal, AChangedIdealFileIsNamed) {
  Fixture f;
  ToothVolume changed = f.ideal;
  changed.voxels.setVoxel(1, 1, 1, makeVoxel(Material::Empty));
  ASSERT_TRUE(saveTooth(f.dir.file("ideal.dvol"), changed).ok());
  std::vector<std::string> warnings;
  auto made = idealForTask(f.task, f.initial, &warnings);
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.message().rfind(f.dir.file("ideal.dvol") + ": the professional's final tooth changed since", 0), 0u)
      << made.message();
}

TEST(TaskIdeal, AChangedSessionFileIsNamed) {
  test::TempDir dir;
  std::ofstream(dir.file("p.dses")) << "not really a session";
  auto hash = fileHash(dir.file("p.dses"));
  ASSERT_TRUE(hash.ok());
  IdealSpec spec;
  spec.kind = IdealKind::Session;
  spec.path = dir.file("p.dses");
  spec.session_hash = hashHex(*hash);
  const ToothVolume tooth = test::enamelSlab();
  EXPECT_TRUE(checkIdealIdentity(spec, tooth, "task t: ideal").ok());
  std::ofstream(dir.file("p.dses")) << "not really a session, edited";
  const Status st = checkIdealIdentity(spec, tooth, "task t: ideal");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind(dir.file("p.dses") + ": the professional's session changed since it was recorded", 0), 0u)
      << st.message();
}

TEST(TaskIdeal, SetIdealRefusesWhatItCannotUse) {
  test::TempDir dir;
  std::ofstream(dir.file("v1.json")) << R"({"format": "dentsim-task", "version": 1, "name": "c", "kind": "caries",)"
                                        R"( "tooth": "builtin:molar", "tools": {"drill": "round_bur_010"}, "target_s": 300,)"
                                        R"( "failure_s": 900, "force_error_n": 3})";
  std::ofstream(dir.file("s.dses")) << "x";
  auto v1 = setTaskIdeal(dir.file("v1.json"), dir.file("s.dses"), "");
  ASSERT_FALSE(v1.ok());
  EXPECT_EQ(v1.message(), dir.file("v1.json") + ": a version 1 task file: set-ideal writes version 2 only (docs/SCORING.md, section 10)");
  std::ofstream(dir.file("v2.json")) << R"({"format": "dentsim-task", "version": 2, "name": "c", "kind": "caries",)"
                                        R"( "tooth": "builtin:molar", "tools": {"drill": "round_bur_010"}, "target_s": 300,)"
                                        R"( "failure_s": 900, "force_error_n": 3})";
  auto bad_session = setTaskIdeal(dir.file("v2.json"), dir.file("s.dses"), "");
  ASSERT_FALSE(bad_session.ok());
  EXPECT_EQ(bad_session.message().rfind(dir.file("s.dses") + ": ", 0), 0u) << bad_session.message();
  // The task file is untouched by a refusal.
  std::ifstream in(dir.file("v2.json"));
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text.find("ideal"), std::string::npos);
}

// ---- the professional's figures ---------------------------------------------------------------------------

constexpr double kDeg = std::numbers::pi / 180.0;

// A drill step: the bur turned by `turn` (its axis is turn applied to +z), `contacts` shell points
// in tissue, the pedal at `pedal`.
SessionStep drillStep(uint64_t k, const Quat& turn, uint32_t contacts, double pedal) {
  SessionStep s;
  s.step = k;
  s.wall_ns = int64_t(k) * 1'000'000;
  s.pens = 0b01;
  s.reading[0].grip.rotation = turn;
  s.reading[0].pedal = pedal;
  s.contacts = {contacts, 0};
  return s;
}

// Bur axes whose mean the hand can work out: 20 degrees about +x is (0, -sin 20, cos 20), about +y
// (sin 20, 0, cos 20); along +x (a quarter turn about +y) is (1, 0, 0).
const Quat kTiltX = Quat::fromAxisAngle({1, 0, 0}, 20 * kDeg);
const Quat kTiltY = Quat::fromAxisAngle({0, 1, 0}, 20 * kDeg);
const Quat kSideways = Quat::fromAxisAngle({0, 1, 0}, 90 * kDeg);

// 4000 steps at 1 kHz (4.0 s): 2000 cutting along kTiltX, 1000 along kTiltY, 500 in contact with
// the pedal up and 500 with the pedal down in the air, both sideways (the mean must skip them).
std::vector<SessionStep> professionalSteps() {
  std::vector<SessionStep> steps;
  for (uint64_t k = 0; k < 4000; ++k) {
    if (k < 2000) steps.push_back(drillStep(k, kTiltX, 12, 0.8));
    else if (k < 3000) steps.push_back(drillStep(k, kTiltY, 3, 1.0));
    else if (k < 3500) steps.push_back(drillStep(k, kSideways, 7, 0.0));
    else steps.push_back(drillStep(k, kSideways, 0, 1.0));
  }
  return steps;
}

// The mean by hand: (2 (0, -s, c) + (s, 0, c)) / 3 = (s, -2s, 3c) / 3, normalized.
Vec3 professionalMeanAxis() {
  const double s = std::sin(20 * kDeg), c = std::cos(20 * kDeg);
  return normalized(Vec3{s, -2 * s, 3 * c});
}

// A folder with the tooth t.dvol (the enamel slab), the professional's final tooth final.dvol (a
// pit cut in it) and a session prof.dses from one to the other, with `steps` and `drill`.
struct ProfessionalFolder {
  test::TempDir dir;
  std::string initial_hash, final_hash;
  explicit ProfessionalFolder(std::vector<SessionStep> steps, const std::string& drill = "fissure_bur_010") {
    ToothVolume initial = test::enamelSlab();
    ToothVolume final_tooth = test::enamelSlab();
    test::setBox(final_tooth, {6, 6, 5}, {10, 10, 8}, makeVoxel(Material::Empty));
    EXPECT_TRUE(saveTooth(dir.file("t.dvol"), initial).ok());
    EXPECT_TRUE(saveTooth(dir.file("final.dvol"), final_tooth).ok());
    initial_hash = volumeHashHex(loadTooth(dir.file("t.dvol"))->voxels, loadTooth(dir.file("t.dvol"))->frame);
    auto loaded_final = loadTooth(dir.file("final.dvol"));
    final_hash = volumeHashHex(loaded_final->voxels, loaded_final->frame);
    SessionRecording r;
    r.info = test::handMadeSessionInfo(initial_hash, initial.voxels.level(), initial.frame.voxel_mm, drill);
    const uint64_t n = steps.size();
    r.steps = std::move(steps);
    r.end = SessionEnd{n, final_hash, "completed"};
    const std::vector<uint8_t> bytes = encodeSession(r);
    std::ofstream(dir.file("prof.dses"), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  // Writes t.json, a version 2 task of `kind_part` on t.dvol with `extra` keys; returns its path.
  std::string task(const std::string& kind_part, const std::string& extra) {
    std::ofstream(dir.file("t.json")) << R"({"format": "dentsim-task", "version": 2, "name": "t", "tooth": "t.dvol",)"
                                         R"( "tools": {"drill": "fissure_bur_010"}, "target_s": 600, "force_error_n": 3, )"
                                      << kind_part << (extra.empty() ? "" : ", " + extra) << "}";
    return dir.file("t.json");
  }
  nlohmann::json written() const {
    std::ifstream in(dir.file("t.json"));
    return nlohmann::json::parse(in);
  }
};

const std::string kCavity = R"("kind": "cavity", "ideal": {"kind": "builtin_path", "path": "class1_cavity"})";

TEST(TaskIdeal, TheTimeRuleIsAQuarterMoreAndNothingLeftAtThreeTimes) {
  // A professional of 8 s: target 10 s; a caries task fails at 24 s; a cavity loses its 25 points
  // between 10 and 24 s, 14 s = 7/30 min, so 25 / (7/30) = 750/7 points a minute.
  const Task caries = timedFromProfessional(test::cariesTask(), 8.0);
  EXPECT_DOUBLE_EQ(caries.target_s, 10.0);
  EXPECT_DOUBLE_EQ(caries.failure_s, 24.0);
  const Task cavity = timedFromProfessional(test::cavityTask(), 8.0);
  EXPECT_DOUBLE_EQ(cavity.target_s, 10.0);
  EXPECT_DOUBLE_EQ(cavity.cavity.time_coefficient, 750.0 / 7.0);
  EXPECT_DOUBLE_EQ(cavity.failure_s, 0.0);
}

TEST(TaskIdeal, TheMeanBurAxisCountsOnlyTheStepsThatCut) {
  SessionRecording r;
  r.steps = professionalSteps();
  const auto mean = meanCuttingBurAxis(r);
  ASSERT_TRUE(mean);
  const Vec3 expected = professionalMeanAxis();
  EXPECT_NEAR(mean->x, expected.x, 1e-12);
  EXPECT_NEAR(mean->y, expected.y, 1e-12);
  EXPECT_NEAR(mean->z, expected.z, 1e-12);
  r.steps.resize(0);
  for (uint64_t k = 0; k < 10; ++k) r.steps.push_back(drillStep(k, kTiltX, 0, 1.0));
  EXPECT_FALSE(meanCuttingBurAxis(r));  // never in contact
}

TEST(TaskIdeal, SetIdealSetsTheKeysTheTaskLeavesToTheProfessional) {
  ProfessionalFolder f(professionalSteps());
  const std::string task = f.task(kCavity, R"("insertion_axis": [0, 0, 1], "from_ideal": ["insertion_axis", "target_s"])");
  auto record = setTaskIdeal(task, f.dir.file("prof.dses"), f.dir.file("final.dvol"));
  ASSERT_TRUE(record.ok()) << record.message();
  EXPECT_DOUBLE_EQ(record->professional.elapsed_s, 4.0);
  EXPECT_DOUBLE_EQ(record->professional.contact_s, 3.5);  // 2000 + 1000 + 500 steps in contact
  EXPECT_EQ(record->professional.drill_tool, "fissure_bur_010");
  const Vec3 expected = professionalMeanAxis();
  // The crown is +z (the slab's frame is the convention's): the angle is acos of the mean's z.
  EXPECT_NEAR(record->professional.bur_axis_from_crown_deg, std::acos(expected.z) / kDeg, 1e-9);
  EXPECT_TRUE(record->axis_set);
  EXPECT_TRUE(record->times_set);

  const nlohmann::json j = f.written();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(j["insertion_axis"][size_t(i)].get<double>(), expected[i], 0.5e-4);
  EXPECT_DOUBLE_EQ(j["target_s"].get<double>(), 5.0);  // 1.25 x 4.0 s
  EXPECT_DOUBLE_EQ(j["cavity"]["time_coefficient"].get<double>(), 25.0 * 60.0 / (1.75 * 4.0));
  // The list stays: a professional recorded again sets them again.
  EXPECT_EQ(j["from_ideal"], nlohmann::json::array({"insertion_axis", "target_s"}));
  EXPECT_EQ(j["ideal"]["kind"], "session");
  EXPECT_EQ(record->task.target_s, 5.0);
}

TEST(TaskIdeal, SetIdealKeepsWhatTheTaskGivesItself) {
  ProfessionalFolder f(professionalSteps(), "round_bur_010");
  const std::string task = f.task(R"("kind": "caries", "failure_s": 900)", R"("insertion_axis": [0, 0, 1])");
  auto record = setTaskIdeal(task, f.dir.file("prof.dses"), f.dir.file("final.dvol"));
  ASSERT_TRUE(record.ok()) << record.message();
  EXPECT_FALSE(record->axis_set);
  EXPECT_FALSE(record->times_set);
  EXPECT_TRUE(record->axis_kept_reason.empty());
  EXPECT_EQ(record->professional.drill_tool, "round_bur_010");  // not the task's fissure bur: the CLI warns
  const nlohmann::json j = f.written();
  EXPECT_EQ(j["insertion_axis"], nlohmann::json::array({0, 0, 1}));
  EXPECT_EQ(j["target_s"], 600);
  EXPECT_EQ(j["failure_s"], 900);
  EXPECT_FALSE(j.contains("from_ideal"));

  // A caries task whose times are left to the professional: failure at 3 x 4.0 s.
  ProfessionalFolder g(professionalSteps());
  g.task(R"("kind": "caries", "failure_s": 900)", R"("from_ideal": ["target_s"])");
  ASSERT_TRUE(setTaskIdeal(g.dir.file("t.json"), g.dir.file("prof.dses"), g.dir.file("final.dvol")).ok());
  EXPECT_DOUBLE_EQ(g.written()["target_s"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(g.written()["failure_s"].get<double>(), 12.0);
  EXPECT_FALSE(g.written().contains("cavity"));
}

TEST(TaskIdeal, AnAxisTheKindCannotHaveIsKeptAndSaidWhy) {
  // A professional who cut only 60 degrees off the crown, on a class I.
  std::vector<SessionStep> steps;
  for (uint64_t k = 0; k < 1000; ++k) steps.push_back(drillStep(k, Quat::fromAxisAngle({1, 0, 0}, 60 * kDeg), 5, 1.0));
  ProfessionalFolder f(std::move(steps));
  f.task(kCavity, R"("cavity_class": "I", "from_ideal": ["insertion_axis"])");
  auto record = setTaskIdeal(f.dir.file("t.json"), f.dir.file("prof.dses"), f.dir.file("final.dvol"));
  ASSERT_TRUE(record.ok()) << record.message();
  EXPECT_FALSE(record->axis_set);
  EXPECT_EQ(record->axis_kept_reason,
            "the professional's mean bur axis points 60 degrees from the tooth's crown axis; a class I cavity's bur "
            "stands within 45 degrees of it");
  EXPECT_EQ(f.written()["target_s"], 600);  // not listed: kept
  EXPECT_FALSE(f.written().contains("insertion_axis"));

  // One who never pressed the pedal in contact: nothing to take an axis from.
  std::vector<SessionStep> idle;
  for (uint64_t k = 0; k < 1000; ++k) idle.push_back(drillStep(k, kTiltX, 5, 0.0));
  ProfessionalFolder g(std::move(idle));
  g.task(kCavity, R"("from_ideal": ["insertion_axis"])");
  auto kept = setTaskIdeal(g.dir.file("t.json"), g.dir.file("prof.dses"), g.dir.file("final.dvol"));
  ASSERT_TRUE(kept.ok()) << kept.message();
  EXPECT_FALSE(kept->professional.bur_axis);
  EXPECT_EQ(kept->axis_kept_reason, "the professional's bur never cut (no step in contact with the pedal down)");
}

}  // namespace
}  // namespace dentsim
